// Compile-time bookkeeping for a list of effects: their names, where each one's parameters sit
// in the model's parameter vector, and calls to whichever hooks each defines.
#pragma once

#include <array>
#include <cstdint>
#include <span>
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

// What a diagnosis knows of each effect (effect.hpp), with the defaults where it declares nothing.
inline constexpr std::string_view kDefaultNeeds = "data in which this effect's inputs vary independently of load and airflow";
template <class E>
constexpr std::string_view needs_of() {
  if constexpr (requires { E::kNeeds; }) return E::kNeeds; else return kDefaultNeeds;
}
template <class E>
constexpr HeatSides sides_of() {
  if constexpr (requires { E::kSides; }) return E::kSides;
  else if constexpr (kind_of<E>() == EffectKind::term && node_of<E>() >= 0)
    return node_of<E>() < kRotorWinding ? HeatSides::stator : HeatSides::rotor;
  else return HeatSides::both;
}
template <class E>
constexpr double score_at_of() {
  if constexpr (requires { E::kScoreAt; }) return E::kScoreAt; else return __builtin_nan("");
}
template <class E>
constexpr std::string_view refit_group_of() {
  if constexpr (requires { E::kRefitGroup; }) return E::kRefitGroup; else return E::kName;
}
template <class E>
constexpr bool refines_group_of() {
  if constexpr (requires { E::kRefinesGroup; }) return E::kRefinesGroup; else return false;
}
template <class E>
constexpr std::span<const WordPart> words_of() {
  if constexpr (requires { E::kWords; }) return std::span<const WordPart>(E::kWords); else return {};
}
using Derived = double (*)(const double*);
template <class E>
constexpr Derived derived_of() {
  if constexpr (requires { &E::derived; }) return &E::derived; else return nullptr;
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
  // A diagnosis's knowledge of each (effect.hpp; NaN score point: the neutral value).
  static constexpr std::array<std::string_view, kCount> kNeeds{needs_of<E>()...};
  static constexpr std::array<HeatSides, kCount> kSides{sides_of<E>()...};
  static constexpr std::array<double, kCount> kScoreAt{score_at_of<E>()...};
  static constexpr std::array<std::string_view, kCount> kRefitGroups{refit_group_of<E>()...};
  static constexpr std::array<bool, kCount> kRefinesGroup{refines_group_of<E>()...};
  static constexpr std::array<std::span<const WordPart>, kCount> kWords{words_of<E>()...};
  static constexpr std::array<Derived, kCount> kDerived{derived_of<E>()...};

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
