#include "smokescan/plot/palette.hpp"

namespace smokescan {

Col colourOf(const std::string& name, size_t index)
{
    static const Col kPalette[] = {{0.15f, 0.3f, 0.9f}, {0.85f, 0.65f, 0.0f}, {0.6f, 0.4f, 0.05f},
                                   {0.1f, 0.6f, 0.2f},  {0.6f, 0.1f, 0.6f},   {0.3f, 0.3f, 0.3f}};
    if (name.find("blue") != std::string::npos) return kPalette[0];
    if (name.find("yellow") != std::string::npos) return kPalette[1];
    if (name.find("gold") != std::string::npos) return kPalette[2];
    return kPalette[(index + 3) % (sizeof kPalette / sizeof kPalette[0])];
}

}  // namespace smokescan
