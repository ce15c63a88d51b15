// core/base/text.h: strict parsing and quoting of command-line and file text, for one-line error messages.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace pv {

// Strict decimal: digits only (no sign, space or leading zero other than "0" itself), at most `max`. nullopt
// otherwise.
std::optional<uint64_t> parse_decimal(const std::string& s, uint64_t max = ~uint64_t(0));
// `s` quoted for an error line: whole if short, else its first 48 characters, "..." and its length.
std::string quote_prefix(const std::string& s);

}  // namespace pv
