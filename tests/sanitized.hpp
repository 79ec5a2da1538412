#pragma once
// Whether the tests run under the address sanitizer (the CI's second leg).

namespace smokescan::test {

/// True in the sanitizer build: it checks memory and undefined behaviour on one run of each
/// path; the Release build checks the statistics over the seeds.
inline bool sanitized()
{
#if defined(__SANITIZE_ADDRESS__)
    return true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
    return true;
#endif
#endif
    return false;
}

}  // namespace smokescan::test
