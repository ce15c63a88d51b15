// core/base/text.cpp: see text.h.
#include "core/base/text.h"

namespace pv {

std::optional<uint64_t> parse_decimal(const std::string& s, uint64_t max) {
    if (s.empty() || s.size() > 20 || (s.size() > 1 && s[0] == '0')) return std::nullopt;
    uint64_t v = 0;
    for (const char c : s) {
        if (c < '0' || c > '9') return std::nullopt;
        const uint64_t d = uint64_t(c - '0');
        if (v > (max - d) / 10) return std::nullopt;  // v * 10 + d > max
        v = v * 10 + d;
    }
    return v;
}

std::string quote_prefix(const std::string& s) {
    constexpr size_t kShown = 48;
    std::string shown = s.size() <= kShown + 16 ? s : s.substr(0, kShown);
    for (char& c : shown)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';  // one line, no terminal controls
    if (shown.size() == s.size()) return "'" + shown + "'";
    return "'" + shown + "...' (" + std::to_string(s.size()) + " bytes)";
}

}  // namespace pv
