// core/render/settings.cpp: describe() and its parse, both from the table of fields (settings.h).
#include "core/render/settings.h"

#include <limits>
#include <sstream>
#include <type_traits>

namespace pv {

std::string RenderSettings::describe() const {
    std::string out;
    for_each_setting([&](const auto& f) {
        using T = std::decay_t<decltype(this->*f.member)>;
        const T v = this->*f.member;
        if (f.omitted && v == *f.omitted) return;
        out += std::string(out.empty() ? "" : " ") + f.key + "=" + f.word(v);
    });
    return out;
}

std::optional<RenderSettings> settings_from_text(const std::string& text) {
    RenderSettings s;
    for_each_setting([&](const auto& f) {
        if (f.omitted) s.*f.member = *f.omitted;  // absent from the text: the value describe() leaves out
    });
    std::stringstream ss(text);
    std::string item;
    bool ok = true;
    while (ok && ss >> item) {
        const size_t eq = item.find('=');
        const std::string key = item.substr(0, eq), value = eq == std::string::npos ? "" : item.substr(eq + 1);
        bool known = false;
        for_each_setting([&](const auto& f) {
            if (known || key != f.key) return;
            known = true;
            using T = std::remove_reference_t<decltype(s.*f.member)>;
            if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
                const std::optional<uint64_t> n = parse_decimal(value, uint64_t(std::numeric_limits<T>::max()));
                if (n) s.*f.member = T(*n);
                ok = n.has_value();
            } else {
                const std::optional<T> v = f.value(value);
                if (v) s.*f.member = *v;
                ok = v.has_value();
            }
        });
        ok = ok && known;
    }
    if (!ok || s.describe() != text) return std::nullopt;
    return s;
}

}  // namespace pv
