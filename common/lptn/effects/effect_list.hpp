// Compile-time bookkeeping for a list of effects: their names, where each one's parameters sit
// in the model's parameter vector, and calls to whichever hooks each defines.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>
#include <utility>

#include "lptn/effects/effect.hpp"

namespace lptn {

// A set of enabled effects, one bit per position in the list.
using EffectSet = std::uint64_t;

namespace internal {
template <class E>
constexpr EffectKind kind_of() {
  if constexpr (requires { E::kKind; }) return E::kKind; else return EffectKind::library;
}
template <class E>
constexpr int node_of() {
  if constexpr (requires { E::kNode; }) return E::kNode; else return -1;
}
template <class E>
constexpr std::string_view formula_of() {
  if constexpr (requires { E::kFormula; }) return E::kFormula; else return {};
}
}  // namespace internal

// A group of effects registered as one entry of an EffectList (the dictionary's terms): the list
// takes its members in order, as if each had been written there.
template <class... E>
struct EffectGroup {};

namespace internal {
template <class... E>
struct FlatEffectList;
template <class Done, class... Rest>
struct Flatten;
template <class... D>
struct Flatten<FlatEffectList<D...>> {
  using type = FlatEffectList<D...>;
};
template <class... D, class... G, class... Rest>
struct Flatten<FlatEffectList<D...>, EffectGroup<G...>, Rest...> : Flatten<FlatEffectList<D..., G...>, Rest...> {};
template <class... D, class E, class... Rest>
struct Flatten<FlatEffectList<D...>, E, Rest...> : Flatten<FlatEffectList<D..., E>, Rest...> {};
}  // namespace internal

// The list of effects E..., groups flattened in place.
template <class... E>
using EffectList = typename internal::Flatten<internal::FlatEffectList<>, E...>::type;

namespace internal {
template <class... E>
struct FlatEffectList {
  static constexpr int kCount = sizeof...(E);
  // Below 64, so that (EffectSet{1} << kCount) - 1, every effect, exists.
  static_assert(kCount < 64, "EffectSet holds 63 effects");

  static constexpr std::array<std::string_view, kCount> kNames{E::kName...};
  static constexpr std::array<std::string_view, kCount> kSummaries{E::kSummary...};
  static constexpr std::array<int, kCount> kParamCounts{static_cast<int>(std::size(E::kParams))...};
  static constexpr std::array<int, kCount> kExtraStates{E::kExtraStates...};
  static constexpr std::array<EffectKind, kCount> kKinds{kind_of<E>()...};
  static constexpr std::array<int, kCount> kNodes{node_of<E>()...};  // terms' node, -1 for library effects
  static constexpr std::array<std::string_view, kCount> kFormulas{formula_of<E>()...};
  static constexpr int kNumParams = (0 + ... + static_cast<int>(std::size(E::kParams)));

  // Offsets of each effect's first parameter, counted from the first effect parameter.
  static constexpr std::array<int, kCount> kParamOffsets = [] {
    std::array<int, kCount> out{};
    int at = 0;
    for (int i = 0; i < kCount; ++i) {
      out[i] = at;
      at += kParamCounts[i];
    }
    return out;
  }();

  // Every effect parameter's spec, in vector order.
  static constexpr std::array<ParamSpec, kNumParams> kParams = [] {
    std::array<ParamSpec, kNumParams> out{};
    int at = 0;
    auto add = [&](const auto& specs) {
      for (const ParamSpec& s : specs) out[at++] = s;
    };
    (add(E::kParams), ...);
    return out;
  }();

  static constexpr int index_of(std::string_view name) {
    for (int i = 0; i < kCount; ++i)
      if (kNames[i] == name) return i;
    return -1;
  }

  // Calls f(std::integral_constant<int, I>{}, E*{nullptr}) for every effect I in `set`.
  template <class F>
  static void for_each_enabled(EffectSet set, F&& f) {
    visit(set, f, std::make_index_sequence<kCount>{});
  }

 private:
  template <class F, std::size_t... I>
  static void visit(EffectSet set, F& f, std::index_sequence<I...>) {
    (((set >> I) & 1 ? f(std::integral_constant<int, static_cast<int>(I)>{}, static_cast<E*>(nullptr))
                      : void()),
     ...);
  }
};
}  // namespace internal

}  // namespace lptn
