#pragma once
/// @file cdr.hpp
/// @brief OMG CDR as ROS 2 serialises messages (encoding "cdr": XCDR1, little-endian, a 4-byte
/// encapsulation header 00 01 00 00, each primitive aligned to its size from the end of that
/// header; strings as a uint32 length counting a closing NUL; sequences as a uint32 count then
/// the elements). Written to the OMG CDR specification (formal/02-06-51, §15.3) and checked against
/// an independent decoder, @foxglove/rosmsg2-serialization (tests/test_bag.cpp).
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

namespace smokescan {

/// Serialises one message.
class CdrWriter {
public:
    CdrWriter();  ///< starts with the little-endian encapsulation header
    template <class T>
    void put(T v)
    {
        static_assert(std::is_arithmetic_v<T>);
        align(sizeof(T));
        raw(&v, sizeof(T));
    }
    void putBool(bool v) { put<uint8_t>(v ? 1 : 0); }
    void putString(const std::string& s);
    /// @brief A sequence of numbers: its count, then the values aligned to their size.
    template <class T>
    void putSequence(const std::vector<T>& v)
    {
        static_assert(std::is_arithmetic_v<T>);
        put<uint32_t>(uint32_t(v.size()));
        if (v.empty()) return;
        align(sizeof(T));
        raw(v.data(), v.size() * sizeof(T));
    }
    const std::vector<uint8_t>& bytes() const { return b_; }

private:
    void align(size_t n);
    void raw(const void* p, size_t n);
    std::vector<uint8_t> b_;
};

/// Decodes one message, every read bounded by the bytes it has.
class CdrReader {
public:
    /// @param what names the message in errors (e.g. "FILE: message 12 on /scan").
    /// @throw Error for a missing or big-endian encapsulation header.
    CdrReader(const uint8_t* data, size_t size, std::string what);
    template <class T>
    T get()
    {
        static_assert(std::is_arithmetic_v<T>);
        align(sizeof(T));
        T v;
        raw(&v, sizeof(T));
        return v;
    }
    bool getBool() { return get<uint8_t>() != 0; }
    std::string getString();
    template <class T>
    std::vector<T> getSequence()
    {
        static_assert(std::is_arithmetic_v<T>);
        const uint32_t n = get<uint32_t>();
        std::vector<T> v;
        if (n == 0) return v;
        align(sizeof(T));
        need(size_t(n) * sizeof(T), "a sequence");
        v.resize(n);
        raw(v.data(), size_t(n) * sizeof(T));
        return v;
    }
    /// @brief A count of elements, each at least `min_bytes`, refused if the rest cannot hold them.
    uint32_t getCount(size_t min_bytes);
    size_t remaining() const { return size_ - pos_; }

private:
    void align(size_t n);
    void need(size_t n, const char* reading) const;
    void raw(void* p, size_t n);
    const uint8_t* data_;
    size_t size_, pos_ = 4;
    std::string what_;
};

}  // namespace smokescan
