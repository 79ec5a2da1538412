#include "smokescan/core/error.hpp"

#include <cstdio>

namespace smokescan {
namespace {

/// Length of the valid UTF-8 sequence starting at s[i] (0 when it is not one); its code point
/// in `cp`.
size_t utf8Length(const std::string& s, size_t i, unsigned& cp)
{
    const auto c = static_cast<unsigned char>(s[i]);
    size_t n = 0;
    unsigned min = 0;
    if (c >= 0xC2 && c <= 0xDF)
        n = 2, min = 0x80;
    else if (c >= 0xE0 && c <= 0xEF)
        n = 3, min = 0x800;
    else if (c >= 0xF0 && c <= 0xF4)
        n = 4, min = 0x10000;
    else
        return 0;
    if (i + n > s.size()) return 0;
    cp = c & (0xFF >> (n + 1));
    for (size_t k = 1; k < n; ++k) {
        const auto d = static_cast<unsigned char>(s[i + k]);
        if ((d & 0xC0) != 0x80) return 0;
        cp = (cp << 6) | (d & 0x3F);
    }
    if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
    return n;
}

/// Code points that would move or hide text on a terminal: C1 controls (U+0080–U+009F, e.g. the
/// CSI U+009B), bidirectional overrides, embeddings and isolates, line and paragraph separators.
bool isHidingControl(unsigned cp)
{
    return (cp >= 0x80 && cp <= 0x9F) || cp == 0x061C || cp == 0x200E || cp == 0x200F ||
        (cp >= 0x2028 && cp <= 0x202E) || (cp >= 0x2066 && cp <= 0x2069);
}

}  // namespace

std::string printable(const std::string& text, size_t max_bytes)
{
    std::string out;
    out.reserve(std::min(text.size(), max_bytes) + 8);
    for (size_t i = 0; i < text.size();) {
        if (out.size() >= max_bytes) {
            out += "…";
            break;
        }
        const auto c = static_cast<unsigned char>(text[i]);
        if (c >= 0x20 && c < 0x7F) {
            out += char(c);
            ++i;
        } else if (unsigned cp = 0; const size_t n = c >= 0x80 ? utf8Length(text, i, cp) : 0) {
            if (isHidingControl(cp)) {
                char buf[16];
                std::snprintf(buf, sizeof buf, "\\u%04X", cp);
                out += buf;
            } else
                out.append(text, i, n);
            i += n;
        } else {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\x%02X", c);
            out += buf;
            ++i;
        }
    }
    return out;
}

std::string printableWhole(const std::string& text)
{
    // Never cut: each byte becomes at most 4 (\xNN; \uXXXX replaces two or three).
    return printable(text, 4 * text.size() + 1);
}

}  // namespace smokescan
