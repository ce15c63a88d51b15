// core/base/text.h: small text helpers shared by the settings, the partial-render format and the command line:
// tables of names for enum values (one table a type, read both ways), strict decimals and quoting for error lines.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace pv {

// One word for a value of an enum (or bool). A table lists every value; the first word of a value is its name, any
// later one an alias that is read but never written.
template <class T>
struct NamedValue {
    const char* name;
    T value;
};

// The name of `v` in `table` (nullptr if absent).
template <class T, size_t N>
constexpr const char* name_of(const NamedValue<T> (&table)[N], T v) {
    for (const NamedValue<T>& e : table)
        if (e.value == v) return e.name;
    return nullptr;
}
// The value named (or aliased) `name` in `table`; nothing for any other word.
template <class T, size_t N>
std::optional<T> value_of(const NamedValue<T> (&table)[N], const std::string& name) {
    for (const NamedValue<T>& e : table)
        if (name == e.name) return e.value;
    return std::nullopt;
}

// Strict decimal: digits only (no sign, space or leading zero other than "0" itself), at most `max`. nullopt
// otherwise.
std::optional<uint64_t> parse_decimal(const std::string& s, uint64_t max = ~uint64_t(0));
// `s` quoted for an error line: whole if short, else its first 48 characters, "..." and its length.
std::string quote_prefix(const std::string& s);

}  // namespace pv
