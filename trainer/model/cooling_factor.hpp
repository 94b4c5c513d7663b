// A motor's cooling factor: every conductance to the cooling air (kConductancesToAir) times one
// number. Motors of one type differ in it a little when new and a lot once a filter clogs or a
// blower weakens; the fleet calibration fits one per motor, the synthetic plant gives each its own.
#pragma once

#include "lptn/model.hpp"

namespace lptn::model {

template <class T, class F>
ParamVector<T> with_cooling_factor(ParamVector<T> p, const F& factor) {
  for (int i : kConductancesToAir) p[i] = p[i] * factor;
  return p;
}

}  // namespace lptn::model
