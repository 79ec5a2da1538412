#include "smokescan/bag/cdr.hpp"

#include <cstring>

#include "smokescan/core/error.hpp"

namespace smokescan {

CdrWriter::CdrWriter() : b_{0x00, 0x01, 0x00, 0x00} {}

void CdrWriter::align(size_t n)
{
    const size_t at = b_.size() - 4;  // alignment counts from the end of the encapsulation header
    b_.resize(b_.size() + (n - at % n) % n, 0);
}

void CdrWriter::raw(const void* p, size_t n)
{
    const auto* c = static_cast<const uint8_t*>(p);
    b_.insert(b_.end(), c, c + n);
}

void CdrWriter::putString(const std::string& s)
{
    put<uint32_t>(uint32_t(s.size() + 1));
    raw(s.data(), s.size());
    b_.push_back(0);
}

CdrReader::CdrReader(const uint8_t* data, size_t size, std::string what)
    : data_(data), size_(size), what_(std::move(what))
{
    if (size < 4) throw Error(what_, "is shorter than a CDR encapsulation header (4 bytes)");
    if (data[0] != 0 || (data[1] != 0 && data[1] != 1))
        throw Error(what_,
                    "is not CDR (encapsulation " + std::to_string(data[0]) + " " + std::to_string(data[1]) + ")");
    if (data[1] == 0) throw Error(what_, "is big-endian CDR, which smokescan does not read");
}

void CdrReader::align(size_t n)
{
    const size_t at = pos_ - 4;
    const size_t pad = (n - at % n) % n;
    need(pad, "padding");
    pos_ += pad;
}

void CdrReader::need(size_t n, const char* reading) const
{
    if (n > size_ - pos_)
        throw Error(what_,
                    "ends at byte " + std::to_string(size_) + " while reading " + reading + " at byte " +
                        std::to_string(pos_) + " (truncated?)");
}

void CdrReader::raw(void* p, size_t n)
{
    need(n, "a value");
    std::memcpy(p, data_ + pos_, n);
    pos_ += n;
}

std::string CdrReader::getString()
{
    const uint32_t n = get<uint32_t>();
    if (n == 0) throw Error(what_, "has a string of length 0 at byte " + std::to_string(pos_) + " (no closing NUL)");
    need(n, "a string");
    const char* p = reinterpret_cast<const char*>(data_ + pos_);
    if (p[n - 1] != '\0') throw Error(what_, "has a string without its closing NUL at byte " + std::to_string(pos_));
    std::string s(p, n - 1);
    pos_ += n;
    return s;
}

uint32_t CdrReader::getCount(size_t min_bytes)
{
    const uint32_t n = get<uint32_t>();
    if (min_bytes > 0 && n > remaining() / min_bytes)
        throw Error(what_,
                    "claims " + std::to_string(n) + " elements at byte " + std::to_string(pos_) + " but has " +
                        std::to_string(remaining()) + " bytes left");
    return n;
}

}  // namespace smokescan
