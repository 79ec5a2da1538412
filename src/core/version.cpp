#include "smokescan/core/version.hpp"

namespace smokescan {

const char* version() { return SMOKESCAN_VERSION; }

}  // namespace smokescan
