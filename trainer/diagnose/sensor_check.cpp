#include "trainer/diagnose/sensor_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>

#include <Eigen/Dense>

#include "hostio/worker_threads.hpp"
#include "trainer/model/simulate.hpp"
#include "trainer/diagnose/drift.hpp"
#include "trainer/diagnose/internal/cycle_span.hpp"
#include "trainer/diagnose/internal/permutation.hpp"

namespace lptn::diagnose {
namespace {

constexpr data::Channel kSensors[] = {data::Channel::stator_winding_c, data::Channel::rotor_c};
constexpr data::FaultShape kShapes[] = {data::FaultShape::offset, data::FaultShape::gain, data::FaultShape::drift};

// A cycle's residuals (model minus reading) with the model run as given, in a fixed order, with
// which sensor each is and the model's value there.
struct Run {
  std::vector<double> r;
  std::vector<float> model, reading;
  std::vector<unsigned char> sensor;  // 0 stator, 1 rotor
};

// What a run reports besides its residuals: each response's change of the residuals, one column
// per response, in the residuals' order (with_responses).
struct Responses {
  int count = 0;
  double* start[4] = {};               // each response's state, starting at its change of the start
  std::vector<double> column[4];       // the model's change at each residual's sensor
};

// `prepared`: prepare_cycle()'s for the cycle's inputs. `responses`, where given, are stepped
// beside the state (the model is affine in its start: a response is exactly how a changed start
// moves every step, without a run of its own).
Run run(const Model<double>& model, const ParamVector<double>& params, const data::Cycle& cycle,
        const model::InitialOffsets<double>& offsets, const model::PreparedCycle& prepared, Responses* responses = nullptr) {
  Run out;
  double x[kMaxStates];
  model::initial_state_for(model, cycle, x, offsets);
  typename Model<double>::template StepWorkspace<double> work;
  for (std::size_t k = 0; k + 1 < cycle.steps; ++k) {
    // Grid step 0 starts at the measurement by construction; step k's result is grid k + 1's.
    if (responses)
      model.step_with_responses(x, prepared[k], params.data(), cycle.dt_s, work, responses->start, responses->count);
    else
      model.step(x, prepared[k], params.data(), cycle.dt_s, work);
    const std::size_t grid = k + 1;
    for (int s = 0; s < 2; ++s) {
      const float y = cycle.at(kSensors[s], grid);
      if (std::isnan(y)) continue;
      const double m = s == 0 ? model.stator_sensor(x) : model.rotor_sensor(x);
      out.r.push_back(m - y);
      out.model.push_back(static_cast<float>(m));
      out.reading.push_back(y);
      out.sensor.push_back(static_cast<unsigned char>(s));
      if (responses)
        for (int c = 0; c < responses->count; ++c)
          responses->column[c].push_back(s == 0 ? model.stator_sensor(responses->start[c])
                                                : model.rotor_sensor(responses->start[c]));
    }
  }
  return out;
}

// The columns of one cycle's linear least-squares problem, each the change of the residuals per
// unit of one explanation. The model is affine in its initial state, and a reading's offset or
// gain moves the start (each measured node starts at its reading) as well as the comparison, so the
// offset and gain columns are exact; the heat balance's are its derivatives in log factor. One run
// gives both of a sensor's: readings 1 K higher move the start by 1 K and every comparison by
// -1 K, readings (1 + g) times theirs move the start by g times the first reading and each
// comparison by -g times its reading, so per unit of g the gain column is the first reading times
// the start's response (the offset column plus one at the sensor's rows) less the readings there.
enum Column { kR0, kStatorCore, kRotorCore, kStatorOffset, kStatorGain, kRotorOffset, kRotorGain, kCooling, kLosses, kColumns };
constexpr int kOffsetColumn[2] = {kStatorOffset, kRotorOffset};
constexpr int kGainColumn[2] = {kStatorGain, kRotorGain};
constexpr double kLogFactorStep = 0.02;

struct CycleFit {
  bool measured[2] = {false, false};
  double n[2] = {0, 0};
  double mean_c[2] = {0, 0};  // the model's mean at the sensor's readings
  double offset_k[2] = {0, 0};  // the best reading offset (reading minus truth, K), the initial offsets refit with it
  double gain[2] = {0, 0};      // the best reading gain (reading over truth, minus one), likewise
  // The cycle's squared error (every sensor) with the initial offsets fitted over the whole cycle
  // and, besides them, one explanation each.
  double sse_offset[2] = {0, 0}, sse_gain[2] = {0, 0}, sse_cooling = 0, sse_losses = 0;
};

// What reading `v` becomes when a sensor's readings are shifted by `shift` K (stored in float, as a
// reading is): the comparison's change, to the bit what a run of the shifted readings compared.
double shifted_reading_change(float v, double shift) { return static_cast<double>(static_cast<float>(v + shift)) - v; }

CycleFit fit_cycle(const Model<double>& model, const ParamVector<double>& params, const data::Cycle& cycle) {
  CycleFit f;
  const model::PreparedCycle prepared = model::prepare_cycle(model, cycle);  // the losses once for its runs
  // The start's changes whose responses one run steps beside the state: a unit offset of each core
  // node, and the start each sensor's readings 1 K higher give (its first reading stored in float).
  const double stator = model::first_valid(cycle, kSensors[0]), rotor = model::first_valid(cycle, kSensors[1]);
  double start[kMaxStates], changed[4][kMaxStates];
  model::initial_state_for(model, cycle, start);
  int response_of[kColumns];
  Responses responses;
  auto add_response = [&](int column, const double* shifted) {
    const int r = responses.count++;
    for (int i = 0; i < kMaxStates; ++i) changed[r][i] = shifted[i] - start[i];
    responses.start[r] = changed[r];
    response_of[column] = r;
  };
  double shifted[kMaxStates];
  model::initial_state_for(model, cycle, shifted, model::InitialOffsets<double>{1.0, 0.0});
  add_response(kStatorCore, shifted);
  model::initial_state_for(model, cycle, shifted, model::InitialOffsets<double>{0.0, 1.0});
  add_response(kRotorCore, shifted);
  for (int s = 0; s < 2; ++s) {
    f.measured[s] = cycle.has(kSensors[s]);
    if (!f.measured[s]) continue;
    const double ds = s == 0 ? shifted_reading_change(static_cast<float>(stator), 1.0) : 0.0;
    const double dr = s == 1 ? shifted_reading_change(static_cast<float>(rotor), 1.0) : 0.0;
    // initial_state_for's rule: where the rotor is not measured, it starts at the stator's reading.
    model.initial_state(shifted, stator + ds, std::isnan(rotor) ? stator + ds : rotor + dr);
    add_response(kOffsetColumn[s], shifted);
  }
  const Run base = run(model, params, cycle, {}, prepared, &responses);
  const std::size_t m = base.r.size();
  if (m == 0) return f;
  std::vector<std::vector<double>> col(kColumns);
  col[kR0] = base.r;
  // A start's column: the model's response, less the readings' own change where they moved.
  for (int c : {kStatorCore, kRotorCore, kStatorOffset, kRotorOffset}) {
    const bool sensor_column = c == kStatorOffset || c == kRotorOffset;
    const int s = c == kRotorOffset ? 1 : 0;
    if (sensor_column && !f.measured[s]) continue;
    std::vector<double>& column = col[static_cast<std::size_t>(c)];
    column = std::move(responses.column[response_of[c]]);
    if (sensor_column)
      for (std::size_t i = 0; i < m; ++i)
        if (base.sensor[i] == s) column[i] -= shifted_reading_change(base.reading[i], 1.0);
  }
  auto difference = [&](int c, const Run& other, double per) {
    col[static_cast<std::size_t>(c)].resize(m);
    for (std::size_t i = 0; i < m; ++i) col[static_cast<std::size_t>(c)][i] = (other.r[i] - base.r[i]) / per;
  };
  for (int s = 0; s < 2; ++s) {
    if (!f.measured[s]) continue;
    const std::vector<double>& offset = col[static_cast<std::size_t>(kOffsetColumn[s])];
    const double first = model::first_valid(cycle, kSensors[s]);
    std::vector<double>& gain = col[static_cast<std::size_t>(kGainColumn[s])];
    gain.resize(m);
    for (std::size_t i = 0; i < m; ++i)
      gain[i] = first * offset[i] + (base.sensor[i] == s ? first - double(base.reading[i]) : 0.0);
  }
  difference(kCooling, run(model, scaled_group(params, DriftGroup::cooling, std::exp(kLogFactorStep)), cycle, {}, prepared), kLogFactorStep);
  difference(kLosses, run(model, scaled_group(params, DriftGroup::losses, std::exp(kLogFactorStep)), cycle, {}, prepared), kLogFactorStep);
  for (std::size_t i = 0; i < m; ++i) {
    f.n[base.sensor[i]] += 1;
    f.mean_c[base.sensor[i]] += base.model[i];
  }
  for (int s = 0; s < 2; ++s)
    if (f.n[s] > 0) f.mean_c[s] /= f.n[s];

  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(kColumns, kColumns);
  for (int a = 0; a < kColumns; ++a)
    for (int b = a; b < kColumns; ++b) {
      const std::vector<double>& x = col[static_cast<std::size_t>(a)];
      const std::vector<double>& y = col[static_cast<std::size_t>(b)];
      if (x.empty() || y.empty()) continue;
      double sum = 0;
      for (std::size_t i = 0; i < m; ++i) sum += x[i] * y[i];
      gram(a, b) = gram(b, a) = sum;
    }
  // min |r0 + sum_j beta_j col_j|^2 over the listed columns: beta and the squared error left.
  auto least_squares = [&](std::initializer_list<int> columns, double* beta_last) {
    const auto k = static_cast<Eigen::Index>(columns.size());
    Eigen::MatrixXd g(k, k);
    Eigen::VectorXd rhs(k);
    Eigen::Index i = 0;
    for (int a : columns) {
      Eigen::Index j = 0;
      for (int b : columns) g(i, j++) = gram(a, b);
      rhs(i++) = -gram(a, kR0);
    }
    // A column the cycle's outputs do not depend on (an offset without its sensor) gets no weight.
    const double ridge = 1e-12 * std::max(g.trace(), 1e-300);
    const Eigen::VectorXd beta = (g + ridge * Eigen::MatrixXd::Identity(k, k)).ldlt().solve(rhs);
    if (beta_last) *beta_last = beta(k - 1);
    return std::max(0.0, gram(kR0, kR0) - rhs.dot(beta));
  };
  for (int s = 0; s < 2; ++s) {
    if (!f.measured[s]) continue;
    double beta = 0;
    f.sse_offset[s] = least_squares({kStatorCore, kRotorCore, kOffsetColumn[s]}, &beta);
    f.offset_k[s] = -beta;  // the readings shifted by beta fit best: the sensor reads -beta off
    f.sse_gain[s] = least_squares({kStatorCore, kRotorCore, kGainColumn[s]}, &beta);
    f.gain[s] = 1 / (1 + beta) - 1;  // the readings times (1 + beta) fit best
  }
  f.sse_cooling = least_squares({kStatorCore, kRotorCore, kCooling}, nullptr);
  f.sse_losses = least_squares({kStatorCore, kRotorCore, kLosses}, nullptr);
  return f;
}

// One cycle of the series: its best reading offset b (K) and, separately, its best reading gain g
// (relative), each with the initial offsets refit beside it; the model's mean there (°C).
struct Point {
  double b = 0, g = 0, mean_c = 0;
};

struct Fit {
  double statistic = 0;  // the reduction of the series' squared deviation, in units of what is left
  data::FaultShape shape = data::FaultShape::offset;
  std::size_t k = 0;  // the first faulty position
  double size = 0;    // a (K) or g (relative)
};

// A cycle's gain is not more precise than kOffsetResolution at 100 °C.
constexpr double kGainResolution = kOffsetResolution / 100.0;

// The regressors of every shape of fault from every position on, centred, with their sums of
// squares: they depend on the positions' files alone, which the orderings of the permutation test
// keep, so they are computed once for the observed series and its 4000 orderings.
struct Regressor {
  data::FaultShape shape;
  std::size_t k;           // the first faulty position
  std::vector<double> xc;  // the fault's weight at each position, less its mean
  double sxx;
};

std::vector<Regressor> regressors(const std::vector<std::size_t>& file, std::size_t files) {
  const std::size_t n = file.size();
  std::vector<Regressor> out;
  std::vector<double> x(n);
  for (data::FaultShape shape : kShapes) {
    // An offset or a gain needs two cycles on either side; a drift may grow from the first cycle.
    const std::size_t k_min = shape == data::FaultShape::drift ? 0 : 2;
    for (std::size_t k = k_min; k + 2 <= n; ++k) {
      data::SensorFault f;
      f.shape = shape;
      f.first = file[k];
      double xm = 0;
      for (std::size_t j = 0; j < n; ++j) xm += (x[j] = f.weight(file[j], files)) / static_cast<double>(n);
      Regressor r{shape, k, std::vector<double>(n), 0.0};
      for (std::size_t j = 0; j < n; ++j) r.sxx += (r.xc[j] = x[j] - xm) * (x[j] - xm);
      if (r.sxx > 0) out.push_back(std::move(r));
    }
  }
  return out;
}

// The largest reduction of a series' squared deviation by one shape of fault from some position
// on: the offset and the drift on the offsets b, the gain on the gains g (a gain fault's offset
// changes with each cycle's temperatures, and the initial offsets take up part of it differently
// in each; its gain does not).
Fit best_fit(const std::vector<Point>& points, const std::vector<Regressor>& regressors) {
  const std::size_t n = points.size();
  Fit best;
  std::vector<double> y(n);
  for (data::FaultShape shape : kShapes) {
    const bool gain = shape == data::FaultShape::gain;
    const double resolution = gain ? kGainResolution : kOffsetResolution;
    double ym = 0;
    for (std::size_t j = 0; j < n; ++j) ym += (y[j] = gain ? points[j].g : points[j].b) / static_cast<double>(n);
    double syy = 0;
    for (std::size_t j = 0; j < n; ++j) syy += (y[j] - ym) * (y[j] - ym);
    for (const Regressor& r : regressors) {
      if (r.shape != shape) continue;
      double sxy = 0;
      for (std::size_t j = 0; j < n; ++j) sxy += r.xc[j] * (y[j] - ym);
      const double explained = sxy * sxy / r.sxx;
      const double left = std::max((syy - explained) / static_cast<double>(n - 2), resolution * resolution);
      const double t = explained / left;
      if (t > best.statistic) best = {t, shape, r.k, sxy / r.sxx};
    }
  }
  return best;
}

void describe(SensorFinding& f, const std::string& first_cycle) {
  const char* name = data::sensor_name(f.sensor);
  char what[256];
  switch (f.fault.shape) {
    case data::FaultShape::offset:
      std::snprintf(what, sizeof what, "the %s sensor reads %.1f K %s from %s on", name, std::abs(f.size_k),
                    f.size_k > 0 ? "high" : "low", first_cycle.c_str());
      break;
    case data::FaultShape::gain:
      std::snprintf(what, sizeof what, "the %s sensor reads %.1f %% %s (%.1f K on average) from %s on", name,
                    100 * std::abs(f.fault.size), f.fault.size > 0 ? "high" : "low", std::abs(f.size_k),
                    first_cycle.c_str());
      break;
    case data::FaultShape::drift:
      std::snprintf(what, sizeof what, "the %s sensor's reading drifts from %s on, %.1f K %s by the last cycle", name,
                    first_cycle.c_str(), std::abs(f.size_k), f.size_k > 0 ? "high" : "low");
      break;
  }
  char evidence[512];
  std::snprintf(evidence, sizeof evidence,
                " (cycles %s; p = %.4f over %d orderings); the heat balance explains those cycles worse: squared error "
                "%.0f K^2 with each cycle's own %s %s against %.0f with its own cooling factor and %.0f with its own "
                "copper-loss factor",
                internal::cycle_span(f.cycles).c_str(), f.p_value, internal::kOrderings, f.sse_sensor, name,
                f.fault.shape == data::FaultShape::gain ? "gain" : "offset", f.sse_cooling, f.sse_losses);
  f.finding = std::string(what) + evidence;
  f.calibrate = data::format_sensor_fault(f.fault, first_cycle);
  f.inspect = std::string("the ") + name + " sensor of these cycles: a replaced or re-wired sensor, its transmitter's zero "
              "and span, its mounting; then calibrate around it (lptn calibrate --sensor-fault) or on the cycles before it";
}

// Sensor `s` (0 stator, 1 rotor) over the cycles that measure it.
SensorFinding check_sensor(int s, const std::vector<CycleFit>& fits, const data::Dataset& dataset,
                           const data::CycleOrder& order, int sensors_checked, int threads) {
  SensorFinding f;
  f.sensor = kSensors[s];
  f.level = kSensorLevel / sensors_checked;
  std::vector<std::size_t> cycles, file;
  std::vector<Point> points;
  for (std::size_t i = 0; i < dataset.cycles.size(); ++i) {
    const CycleFit& c = fits[i];
    if (!(c.n[s] > 0)) continue;
    cycles.push_back(i);
    file.push_back(order.file_index[i]);
    points.push_back({c.offset_k[s], c.gain[s], c.mean_c[s]});
    f.offsets.push_back({dataset.cycles[i].name, c.offset_k[s], c.gain[s], c.mean_c[s]});
  }
  const std::size_t n = points.size();
  f.fault.sensor = f.sensor;
  if (n < 4) {
    f.finding = std::string("fewer than four cycles read the ") + data::sensor_name(f.sensor) + " sensor: not checked";
    return f;
  }
  const std::vector<Regressor> fault_regressors = regressors(file, order.files);
  const Fit fit = best_fit(points, fault_regressors);
  f.statistic = fit.statistic;
  // The positions keep their files; the cycles' (b, M) move between them.
  f.p_value = internal::p_value(points, fit.statistic,
                                [&](const std::vector<Point>& p) { return best_fit(p, fault_regressors).statistic; }, threads);
  f.fault.shape = fit.shape;
  f.fault.size = fit.size;
  f.fault.first = file[fit.k];
  double faulty_mean_c = 0;
  std::vector<std::size_t> faulty;
  for (std::size_t j = fit.k; j < n; ++j) {
    faulty.push_back(cycles[j]);
    f.cycles.push_back(dataset.cycles[cycles[j]].name);
    faulty_mean_c += points[j].mean_c;
  }
  faulty_mean_c /= static_cast<double>(faulty.size());
  f.size_k = fit.shape == data::FaultShape::gain ? fit.size * faulty_mean_c : fit.size;
  const std::string first_cycle = dataset.cycles[cycles[fit.k]].file.stem().string();
  char shift[256];
  std::snprintf(shift, sizeof shift, "the %s sensor's readings shift by %+.2f K (%s) from %s on (p = %.4f, at most %.4f)",
                data::sensor_name(f.sensor), f.size_k, data::to_string(fit.shape), first_cycle.c_str(), f.p_value, f.level);
  if (f.p_value > f.level || std::abs(f.size_k) < kMinSensorFaultK) {
    f.finding = std::string(shift) + (f.p_value > f.level ? ": not significant" : ": too small to tell from the model's own misfit");
    f.cycles.clear();
    return f;
  }
  // The heat balance's alternative, cycle by cycle over the faulty ones.
  for (std::size_t i : faulty) {
    const CycleFit& c = fits[i];
    f.sse_sensor += fit.shape == data::FaultShape::gain ? c.sse_gain[s] : c.sse_offset[s];
    f.sse_cooling += c.sse_cooling;
    f.sse_losses += c.sse_losses;
  }
  if (!(f.sse_sensor < f.sse_cooling && f.sse_sensor < f.sse_losses)) {
    char why[256];
    std::snprintf(why, sizeof why, ", but the heat balance explains those cycles as well or better (squared error %.0f K^2 "
                  "with each cycle's own sensor %s, %.0f with its own cooling factor, %.0f with its own copper-loss "
                  "factor): the motor changed, not the sensor", f.sse_sensor, data::to_string(fit.shape), f.sse_cooling,
                  f.sse_losses);
    f.finding = std::string(shift) + why;
    f.cycles.clear();
    return f;
  }
  f.found = true;
  describe(f, first_cycle);
  return f;
}

}  // namespace

std::vector<SensorFinding> check_sensors(const Model<double>& model, const ParamVector<double>& params,
                                         const data::Dataset& dataset, int threads) {
  std::vector<CycleFit> fits(dataset.cycles.size());
  hostio::parallel_for(dataset.cycles.size(), threads,
               [&](std::size_t i) { fits[i] = fit_cycle(model, params, dataset.cycles[i]); });
  const data::CycleOrder order = data::cycle_order(dataset);
  std::vector<int> measured;
  for (int s = 0; s < 2; ++s)
    for (const data::Cycle& c : dataset.cycles)
      if (c.has(kSensors[s])) {
        measured.push_back(s);
        break;
      }
  std::vector<SensorFinding> out;
  for (int s : measured)
    out.push_back(check_sensor(s, fits, dataset, order, static_cast<int>(measured.size()), threads));
  return out;
}

nlohmann::json to_json(const SensorFinding& f) {
  nlohmann::json offsets = nlohmann::json::array();
  for (const CycleOffset& o : f.offsets) offsets.push_back({{"cycle", o.cycle}, {"offset_k", o.offset_k}, {"gain", o.gain}, {"mean_c", o.mean_c}});
  return {{"sensor", data::sensor_name(f.sensor)},
          {"found", f.found},
          {"shape", data::to_string(f.fault.shape)},
          {"size", f.fault.size},
          {"size_k", f.size_k},
          {"cycles", f.cycles},
          {"statistic", f.statistic},
          {"p_value", f.p_value},
          {"level", f.level},
          {"finding", f.finding},
          {"inspect", f.inspect},
          {"calibrate", f.calibrate},
          {"heat_balance", {{"sse_sensor_k2", f.sse_sensor}, {"sse_cooling_k2", f.sse_cooling}, {"sse_losses_k2", f.sse_losses}}},
          {"offsets", offsets}};
}

}  // namespace lptn::diagnose
