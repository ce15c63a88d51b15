// tests/support/field_count.h: the number of fields of an aggregate, counted by the longest brace list that
// initialises it (each element converts to any field type). Tests compare it with a hand-written list of the
// fields (a settings table, a hash's coverage) so that a field added to the struct and not to the list shows.
#pragma once

#include <cstddef>
#include <type_traits>
#include <utility>

namespace pv::test {

struct AnyField {
    template <class T>
    constexpr operator T() const {
        return T{};
    }
};
template <class T, class Seq, class = void>
struct BraceInit : std::false_type {};
template <class T, size_t... I>
struct BraceInit<T, std::index_sequence<I...>, std::void_t<decltype(T{(void(I), AnyField{})...})>> : std::true_type {};
template <class T, size_t N = 0>
constexpr size_t field_count() {
    if constexpr (BraceInit<T, std::make_index_sequence<N + 1>>::value)
        return field_count<T, N + 1>();
    else
        return N;
}

}  // namespace pv::test
