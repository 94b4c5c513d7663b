// The initial offsets of the nodes no sensor sees (InitialOffsets, simulate.hpp), estimated for
// one cycle and given parameters from the cycle's first minutes.
#pragma once

#include "lptn/model.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/model/simulate.hpp"

namespace lptn::model {

// How far (K) an unmeasured node may start from the rule's value: calibration's bound on the
// offsets, and this estimate's.
inline constexpr double kInitialOffsetBoundK = 40.0;
// The window of the cycle's start the estimate below fits the offsets on, by default.
inline constexpr double kInitialOffsetWindowS = 600.0;

// Least squares of model minus measurement (the stator winding sensor and, where measured, the
// rotor) over the cycle's first `window_s` seconds, with the parameters held, each offset within
// +-kInitialOffsetBoundK. Calibration fits the offsets jointly with the parameters for its training
// cycles; any other cycle (a test cycle, the metrics, a TD3 episode, the report) gets them here.
//
// With the parameters held, the model is affine in its initial state (the step is x' = A x + c,
// A and c set by the inputs and parameters alone), so every output is y0 + a s + b r in the two
// offsets s and r: one run gives y0, with a and b stepped beside it without the input term
// through each step's one assembly and factorisation (three runs did both three times), and the
// bounded two-parameter least-squares problem is solved in closed form. A cycle with no
// measurement in the window, or an offset the window's outputs do not depend on, gets 0.
// `prepared`, where given, is prepare_cycle()'s for this model and cycle (run_cycle).
InitialOffsets<double> estimate_initial_offsets(const Model<double>& model, const ParamVector<double>& params,
                                               const data::Cycle& cycle, double window_s = kInitialOffsetWindowS,
                                               const PreparedCycle* prepared = nullptr);

// estimate_initial_offsets() for L (2 or 4) parameter sets at once, out[l] for params[l], each the
// bits the one-set call gives (lanes.hpp): for a caller that scores many sets on one cycle.
template <int L>
void estimate_initial_offsets_lanes(const Model<double>& model, const ParamVector<double>* params,
                                    const data::Cycle& cycle, InitialOffsets<double>* out,
                                    double window_s = kInitialOffsetWindowS, const PreparedCycle* prepared = nullptr);

}  // namespace lptn::model
