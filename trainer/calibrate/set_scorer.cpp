#include "trainer/calibrate/set_scorer.hpp"

#include <algorithm>
#include <cmath>

#include "hostio/worker_threads.hpp"
#include "trainer/model/initial_offsets.hpp"
#include "trainer/model/simulate.hpp"

namespace lptn::calibrate {

constexpr std::size_t kSplits = kResidualSplits.size();

struct SetScorer::Sums {
  struct Sensor {
    double n = 0, sum = 0, sum2 = 0;
    std::array<double, kSplits> n_in{}, sum_in{};
  } sensor[2];
  std::size_t steps = 0;
};

namespace {

double median(std::vector<float> v) {
  std::erase_if(v, [](float x) { return std::isnan(x); });
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// The stator measurement's change over a minute centred on k (NaN where it cannot be taken).
float heating_rate(const data::Cycle& c, std::size_t k) {
  const auto half = static_cast<std::size_t>(std::max(1.0, std::round(30.0 / c.dt_s)));
  if (k < half || k + half >= c.steps) return std::nanf("");
  return c.at(data::Channel::stator_winding_c, k + half) - c.at(data::Channel::stator_winding_c, k - half);
}

}  // namespace

SetScorer::SetScorer(const Model<double>& model, FreeParameters free, const ParamVector<double>& fixed,
                     std::vector<data::Cycle> cycles)
    : model_(model), free_(std::move(free)), fixed_(fixed), cycles_(std::move(cycles)) {
  using data::Channel;
  // The medians the splits cut at, over every cycle's samples.
  std::array<std::vector<float>, kSplits> values;
  auto quantity = [](const data::Cycle& c, std::size_t s, std::size_t k) -> float {
    switch (s) {
      case 0: return c.at(Channel::airflow_m3s, k);
      case 1: return c.at(Channel::current_a, k);
      case 2: return std::abs(c.at(Channel::speed_rpm, k));
      case 3: return heating_rate(c, k);
      case 4: return c.at(Channel::stator_winding_c, k);
      case 5: return static_cast<float>(static_cast<double>(k) * c.dt_s);
      default: return c.at(Channel::ambient_c, k);
    }
  };
  for (const data::Cycle& c : cycles_)
    for (std::size_t k = 0; k < c.steps; ++k)
      for (std::size_t s = 0; s < kSplits; ++s) values[s].push_back(quantity(c, s, k));
  std::array<double, kSplits> cut{};
  for (std::size_t s = 0; s < kSplits; ++s) cut[s] = median(std::move(values[s]));
  cut[3] = 0.0;    // heating: rising at all
  cut[5] = 600.0;  // the first ten minutes (the split holds below the cut, see below)
  for (const data::Cycle& c : cycles_) prepared_.push_back(model::prepare_cycle(model_, c));
  for (const data::Cycle& c : cycles_) {
    std::vector<std::uint8_t> bits(c.steps, 0);
    for (std::size_t k = 0; k < c.steps; ++k)
      for (std::size_t s = 0; s < kSplits; ++s) {
        const float q = quantity(c, s, k);
        const bool holds = s == 5 ? q < cut[s] : q > cut[s];
        if (!std::isnan(q) && holds) bits[k] |= static_cast<std::uint8_t>(1u << s);
      }
    split_bits_.push_back(std::move(bits));
  }
}

ParamVector<double> SetScorer::params_for(const double* u) const {
  ParamVector<double> p = fixed_;
  for (std::size_t j = 0; j < free_.size(); ++j)
    p[free_.index[j]] = from_normalized(std::clamp(u[j], -1.0, 1.0), free_.min[j], free_.max[j]);
  return p;
}

namespace {

// One step's residuals into a set's sums (the cycle's sample k, the model's two readings).
void add_step(SetScorer::Sums& sums, const data::Cycle& c, const std::vector<std::uint8_t>& bits, std::size_t k,
              const double (&model_reading)[2]) {
  using data::Channel;
  const float measured[2] = {c.at(Channel::stator_winding_c, k), c.at(Channel::rotor_c, k)};
  for (int s = 0; s < 2; ++s) {
    if (std::isnan(measured[s])) continue;
    const double r = model_reading[s] - measured[s];
    SetScorer::Sums::Sensor& t = sums.sensor[s];
    t.n += 1;
    t.sum += r;
    t.sum2 += r * r;
    for (std::size_t b = 0; b < kSplits; ++b)
      if (bits[k] & (1u << b)) {
        t.n_in[b] += 1;
        t.sum_in[b] += r;
      }
  }
}

// Sets side by side on one cycle (run<L>: L lanes, the first `count` read).
struct SideBySide {
  const Model<double>& model;
  const data::Cycle& c;
  const std::vector<std::uint8_t>& bits;
  const model::PreparedCycle* prepared;
  const ParamVector<double>* p;
  std::size_t count;
  SetScorer::Sums* sums;

  template <int L>
  void run() const {
    ParamVector<double> lane_params[L];
    for (int l = 0; l < L; ++l) lane_params[l] = p[std::min(static_cast<std::size_t>(l), count - 1)];
    model::InitialOffsets<double> lane_offsets[L];
    model::estimate_initial_offsets_lanes<L>(model, lane_params, c, lane_offsets, model::kInitialOffsetWindowS, prepared);
    model::run_cycle_lanes<L>(model, lane_params, c, [&](std::ptrdiff_t step, const Lanes<L>* x) {
      const auto k = static_cast<std::size_t>(step + 1);
      const Lanes<L>& stator = model.stator_sensor(x);
      const Lanes<L>& rotor = model.rotor_sensor(x);
      for (std::size_t l = 0; l < count; ++l) {
        const double model_reading[2] = {stator.lane(static_cast<int>(l)), rotor.lane(static_cast<int>(l))};
        add_step(sums[l], c, bits, k, model_reading);
      }
    }, lane_offsets, prepared);
  }
};

}  // namespace

void SetScorer::score_cycle(const ParamVector<double>* p, std::size_t count, std::size_t ci, Sums* sums) const {
  const data::Cycle& c = cycles_[ci];
  const std::vector<std::uint8_t>& bits = split_bits_[ci];
  const model::PreparedCycle* prepared = &prepared_[ci];
  for (std::size_t l = 0; l < count; ++l) sums[l].steps = evaluation_steps(c);
  if (count == 1) {
    const model::InitialOffsets<double> offsets =
        model::estimate_initial_offsets(model_, p[0], c, model::kInitialOffsetWindowS, prepared);  // the metrics' own fit
    model::run_cycle(model_, p[0].data(), c, [&](std::ptrdiff_t step, const double* x) {
      const double model_reading[2] = {model_.stator_sensor(x), model_.rotor_sensor(x)};
      add_step(sums[0], c, bits, static_cast<std::size_t>(step + 1), model_reading);
    }, offsets, SIZE_MAX, prepared);
    return;
  }
  // Two to kLanes sets side by side, each lane with a double's bits (the offsets' fit too); lanes
  // past `count` repeat the last set and are not read.
  const SideBySide work{model_, c, bits, prepared, p, count, sums};
  if (count == 2)
    work.run<2>();
  else
    run_on_widest_lanes([&] { work.run<4>(); });
}

void SetScorer::score(const double* u, std::size_t n, SetScore* out, int threads) const {
  const std::size_t p = free_.size(), nc = cycles_.size();
  std::vector<ParamVector<double>> params(n);
  for (std::size_t i = 0; i < n; ++i) params[i] = params_for(u + i * p);
  // Sets kLanes at a time on each cycle: item (group g, cycle ci) holds its sets' sums side by side.
  const std::size_t groups = (n + kLanes - 1) / kLanes;
  std::vector<Sums> sums(groups * nc * kLanes);
  hostio::parallel_for(groups * nc, threads, [&](std::size_t item) {
    const std::size_t first = item / nc * kLanes;
    score_cycle(&params[first], std::min(kLanes, n - first), item % nc, &sums[item * kLanes]);
  });
  constexpr double kScaleK = 0.2;
  for (std::size_t i = 0; i < n; ++i) {
    Sums total;
    for (std::size_t ci = 0; ci < nc; ++ci) {  // a fixed order: the same sums on any number of threads
      const Sums& s = sums[((i / kLanes) * nc + ci) * kLanes + i % kLanes];
      total.steps += s.steps;
      for (int k = 0; k < 2; ++k) {
        Sums::Sensor& t = total.sensor[k];
        t.n += s.sensor[k].n;
        t.sum += s.sensor[k].sum;
        t.sum2 += s.sensor[k].sum2;
        for (std::size_t b = 0; b < kSplits; ++b) {
          t.n_in[b] += s.sensor[k].n_in[b];
          t.sum_in[b] += s.sensor[k].sum_in[b];
        }
      }
    }
    SetScore& o = out[i];
    o.simulated_steps = total.steps;
    o.features.assign(features(), 0.0f);
    double n_all = 0, sum2_all = 0;
    double* rmse[2] = {&o.stator_rmse_k, &o.rotor_rmse_k};
    for (int k = 0; k < 2; ++k) {
      const Sums::Sensor& t = total.sensor[k];
      n_all += t.n;
      sum2_all += t.sum2;
      if (t.n == 0) continue;
      *rmse[k] = std::sqrt(t.sum2 / t.n);
      float* f = o.features.data() + k * kPerSensor;
      f[0] = static_cast<float>(std::log(*rmse[k] + 1e-3));
      f[1] = static_cast<float>(std::asinh(t.sum / t.n / kScaleK));
      for (std::size_t b = 0; b < kSplits; ++b) {
        const double n_out = t.n - t.n_in[b];
        if (t.n_in[b] == 0 || n_out == 0) continue;
        const double diff = t.sum_in[b] / t.n_in[b] - (t.sum - t.sum_in[b]) / n_out;
        f[2 + b] = static_cast<float>(std::asinh(diff / kScaleK));
      }
    }
    o.rmse_k = n_all > 0 ? std::sqrt(sum2_all / n_all) : 0.0;
  }
}

}  // namespace lptn::calibrate
