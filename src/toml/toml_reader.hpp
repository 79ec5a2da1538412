#pragma once
// Internal: strict reading of TOML tables. Every key must be read or it is reported as unknown;
// every error names "FILE:LINE: key: problem".
#include <toml++/toml.h>

#include <set>
#include <string>
#include <vector>

#include "smokescan/core/error.hpp"
#include "smokescan/core/ray.hpp"

namespace smokescan {

class TomlTable {
public:
    TomlTable(const toml::table& t, std::string source, std::string path)
        : t_(t), source_(std::move(source)), path_(std::move(path))
    {
    }

    bool has(const std::string& key) const { return t_.contains(key); }
    const std::string& source() const { return source_; }

    /// Numbers (integers accepted), finite.
    double num(const std::string& key, double def) { return has(key) ? numReq(key) : def; }
    double numReq(const std::string& key)
    {
        const toml::node* n = get(key);
        if (auto v = n->value<double>()) {
            if (!std::isfinite(*v)) fail(n, key, "must be a finite number");
            return *v;
        }
        fail(n, key, "must be a number");
    }
    double positive(const std::string& key, double def)
    {
        const double v = num(key, def);
        if (!(v > 0)) fail(t_.get(key), key, "must be > 0");
        return v;
    }
    double nonneg(const std::string& key, double def)
    {
        const double v = num(key, def);
        if (!(v >= 0)) fail(t_.get(key), key, "must be >= 0");
        return v;
    }
    /// A number in [lo, hi] (the unit is the caller's).
    double between(const std::string& key, double def, double lo, double hi)
    {
        const double v = num(key, def);
        if (!(v >= lo && v <= hi)) {
            char buf[96];
            std::snprintf(buf, sizeof buf, "must be in [%g, %g]", lo, hi);
            fail(t_.get(key), key, buf);
        }
        return v;
    }
    long long integer(const std::string& key, long long def)
    {
        if (!has(key)) return def;
        const toml::node* n = get(key);
        if (auto v = n->value_exact<int64_t>()) return *v;
        fail(n, key, "must be an integer");
    }
    bool boolean(const std::string& key, bool def)
    {
        if (!has(key)) return def;
        const toml::node* n = get(key);
        if (auto v = n->value_exact<bool>()) return *v;
        fail(n, key, "must be true or false");
    }
    std::string str(const std::string& key, const std::string& def) { return has(key) ? strReq(key) : def; }
    std::string strReq(const std::string& key)
    {
        const toml::node* n = get(key);
        if (auto v = n->value_exact<std::string>()) return *v;
        fail(n, key, "must be a string");
    }
    Vec3 vec3(const std::string& key, const Vec3& def) { return has(key) ? vec3Req(key) : def; }
    Vec3 vec3Req(const std::string& key)
    {
        const toml::node* n = get(key);
        const toml::array* a = n->as_array();
        if (!a || a->size() != 3) fail(n, key, "must be an array of 3 numbers");
        Vec3 v;
        for (size_t i = 0; i < 3; ++i) {
            auto x = (*a)[i].value<double>();
            if (!x || !std::isfinite(*x)) fail(n, key, "must be an array of 3 finite numbers");
            v[int(i)] = *x;
        }
        return v;
    }
    /// An array of finite numbers (at most `max_count`).
    std::vector<double> numbers(const std::string& key, size_t max_count)
    {
        const toml::node* n = get(key);
        const toml::array* a = n->as_array();
        if (!a) fail(n, key, "must be an array of numbers");
        if (a->size() > max_count) fail(n, key, "has more than " + std::to_string(max_count) + " values");
        std::vector<double> out;
        for (const auto& e : *a) {
            auto x = e.value<double>();
            if (!x || !std::isfinite(*x)) fail(&e, key, "must hold finite numbers");
            out.push_back(*x);
        }
        return out;
    }
    /// An array of strings (at most `max_count`).
    std::vector<std::string> strings(const std::string& key, size_t max_count)
    {
        const toml::node* n = get(key);
        const toml::array* a = n->as_array();
        if (!a) fail(n, key, "must be an array of strings");
        if (a->size() > max_count) fail(n, key, "has more than " + std::to_string(max_count) + " values");
        std::vector<std::string> out;
        for (const auto& e : *a) {
            auto x = e.value_exact<std::string>();
            if (!x) fail(&e, key, "must hold strings");
            out.push_back(*x);
        }
        return out;
    }
    /// An array of [a, b] pairs of numbers.
    std::vector<std::pair<double, double>> pairs(const std::string& key)
    {
        const toml::node* n = get(key);
        const toml::array* a = n->as_array();
        if (!a) fail(n, key, "must be an array of [a, b] pairs");
        std::vector<std::pair<double, double>> out;
        for (const auto& e : *a) {
            const toml::array* p = e.as_array();
            if (!p || p->size() != 2) fail(&e, key, "must be an array of [a, b] pairs");
            auto x = (*p)[0].value<double>(), y = (*p)[1].value<double>();
            if (!x || !y || !std::isfinite(*x) || !std::isfinite(*y)) fail(&e, key, "pairs must hold finite numbers");
            out.emplace_back(*x, *y);
        }
        return out;
    }
    TomlTable table(const std::string& key)
    {
        const toml::node* n = get(key);
        if (!n->is_table()) fail(n, key, "must be a table");
        return TomlTable(*n->as_table(), source_, qualify(key));
    }
    /// An array of tables ([[key]]); empty when absent.
    std::vector<TomlTable> tables(const std::string& key)
    {
        std::vector<TomlTable> out;
        if (!has(key)) return out;
        const toml::node* n = get(key);
        const toml::array* a = n->as_array();
        if (!a) fail(n, key, "must be an array of tables ([[" + key + "]])");
        for (size_t i = 0; i < a->size(); ++i) {
            const toml::table* t = (*a)[i].as_table();
            if (!t) fail(&(*a)[i], key, "must be an array of tables ([[" + key + "]])");
            out.emplace_back(*t, source_, qualify(key) + "[" + std::to_string(i) + "]");
        }
        return out;
    }
    bool isString(const std::string& key) const { return has(key) && t_.get(key)->is_string(); }

    /// Rejects keys that were never read.
    /// Refuses any key not read; `what` (e.g. "a point light") names whose keys they are not.
    void finish(const std::string& what = "") const
    {
        for (const auto& [k, v] : t_)
            if (!used_.count(std::string(k.str())))
                throw Error(where(&v),
                            "unknown key '" + qualify(std::string(k.str())) + "'" +
                                (what.empty() ? "" : ": not a key of " + what));
    }
    [[noreturn]] void error(const std::string& key, const std::string& problem) const
    {
        fail(has(key) ? t_.get(key) : nullptr, key, problem);
    }
    [[noreturn]] void error(const std::string& problem) const
    {
        throw Error(where(&t_), (path_.empty() ? "" : path_ + ": ") + problem);
    }

private:
    const toml::node* get(const std::string& key)
    {
        const toml::node* n = t_.get(key);
        if (!n) throw Error(where(&t_), "missing field '" + qualify(key) + "'");
        used_.insert(key);
        return n;
    }
    std::string qualify(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
    std::string where(const toml::node* n) const
    {
        if (n && n->source().begin.line > 0) return source_ + ":" + std::to_string(n->source().begin.line);
        return source_;
    }
    [[noreturn]] void fail(const toml::node* n, const std::string& key, const std::string& problem) const
    {
        throw Error(where(n ? n : &t_), qualify(key) + " " + problem);
    }

    const toml::table& t_;
    std::string source_, path_;
    std::set<std::string> used_;
};

/// Parses TOML text; syntax errors become "SOURCE:LINE: problem".
inline toml::table parseToml(const std::string& text, const std::string& source)
{
    try {
        return toml::parse(text, source);
    } catch (const toml::parse_error& e) {
        throw Error(source + ":" + std::to_string(e.source().begin.line), std::string(e.description()));
    }
}

}  // namespace smokescan
