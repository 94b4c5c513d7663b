#include "trainer/search/internal/cma_es.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>

#include <Eigen/Dense>

namespace lptn::search {

struct CmaEs::Impl {
  std::size_t n;
  int lambda, mu;
  Eigen::VectorXd weights;
  double mueff, cc, cs, c1, cmu, damps, chi_n;
  Eigen::VectorXd mean, pc, ps, diag;  // diag: square roots of C's eigenvalues
  Eigen::MatrixXd C, B;
  double sigma;
  int generation = 0;
  std::mt19937_64 rng;
  Eigen::MatrixXd asked;  // n x lambda
  std::vector<double> mean_out;

  void decompose() {
    C = (C + C.transpose()) / 2;  // against drift from symmetry
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(C);
    B = eig.eigenvectors();
    diag = eig.eigenvalues().cwiseMax(1e-300).cwiseSqrt();
  }
};

CmaEs::CmaEs(std::vector<double> mean, double sigma, std::uint64_t seed, int lambda) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.n = mean.size();
  if (s.n == 0 || !(sigma > 0)) throw std::invalid_argument("CmaEs: a dimension and a positive sigma are needed");
  const double n = static_cast<double>(s.n);
  s.lambda = lambda > 0 ? lambda : 4 + static_cast<int>(std::floor(3 * std::log(n)));
  s.mu = s.lambda / 2;
  s.weights.resize(s.mu);
  for (int i = 0; i < s.mu; ++i) s.weights[i] = std::log(s.mu + 0.5) - std::log(i + 1.0);
  s.weights /= s.weights.sum();
  s.mueff = 1.0 / s.weights.squaredNorm();
  s.cc = (4 + s.mueff / n) / (n + 4 + 2 * s.mueff / n);
  s.cs = (s.mueff + 2) / (n + s.mueff + 5);
  s.c1 = 2 / ((n + 1.3) * (n + 1.3) + s.mueff);
  s.cmu = std::min(1 - s.c1, 2 * (s.mueff - 2 + 1 / s.mueff) / ((n + 2) * (n + 2) + s.mueff));
  s.damps = 1 + 2 * std::max(0.0, std::sqrt((s.mueff - 1) / (n + 1)) - 1) + s.cs;
  s.chi_n = std::sqrt(n) * (1 - 1 / (4 * n) + 1 / (21 * n * n));
  s.mean = Eigen::Map<Eigen::VectorXd>(mean.data(), static_cast<Eigen::Index>(s.n));
  s.pc = s.ps = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(s.n));
  s.C = Eigen::MatrixXd::Identity(static_cast<Eigen::Index>(s.n), static_cast<Eigen::Index>(s.n));
  s.sigma = sigma;
  s.rng.seed(seed);
  s.decompose();
  s.mean_out = mean;
}

CmaEs::~CmaEs() = default;

int CmaEs::lambda() const { return impl_->lambda; }
std::size_t CmaEs::dimension() const { return impl_->n; }
double CmaEs::sigma() const { return impl_->sigma; }
const std::vector<double>& CmaEs::mean() const { return impl_->mean_out; }

std::vector<double> CmaEs::ask() {
  Impl& s = *impl_;
  std::normal_distribution<double> normal;
  const auto n = static_cast<Eigen::Index>(s.n);
  s.asked.resize(n, s.lambda);
  for (int k = 0; k < s.lambda; ++k) {
    Eigen::VectorXd z(n);
    for (Eigen::Index i = 0; i < n; ++i) z[i] = normal(s.rng);
    s.asked.col(k) = s.mean + s.sigma * (s.B * s.diag.cwiseProduct(z));
  }
  std::vector<double> out(s.n * static_cast<std::size_t>(s.lambda));
  for (int k = 0; k < s.lambda; ++k)
    for (Eigen::Index i = 0; i < n; ++i) out[static_cast<std::size_t>(k) * s.n + static_cast<std::size_t>(i)] = s.asked(i, k);
  return out;
}

void CmaEs::tell(const std::vector<double>& costs) {
  Impl& s = *impl_;
  if (costs.size() != static_cast<std::size_t>(s.lambda)) throw std::invalid_argument("CmaEs::tell: one cost per asked point");
  std::vector<int> order(static_cast<std::size_t>(s.lambda));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return costs[static_cast<std::size_t>(a)] < costs[static_cast<std::size_t>(b)]; });
  const auto n = static_cast<Eigen::Index>(s.n);
  const Eigen::VectorXd old = s.mean;
  Eigen::MatrixXd y(n, s.mu);  // the best mu steps, in units of sigma
  for (int i = 0; i < s.mu; ++i) y.col(i) = (s.asked.col(order[static_cast<std::size_t>(i)]) - old) / s.sigma;
  const Eigen::VectorXd yw = y * s.weights;
  s.mean = old + s.sigma * yw;
  // C^(-1/2) yw = B D^-1 B^T yw
  const Eigen::VectorXd whitened = s.B * (s.B.transpose() * yw).cwiseQuotient(s.diag);
  s.ps = (1 - s.cs) * s.ps + std::sqrt(s.cs * (2 - s.cs) * s.mueff) * whitened;
  ++s.generation;
  const double ps_norm = s.ps.norm();
  const bool hsig = ps_norm / std::sqrt(1 - std::pow(1 - s.cs, 2.0 * s.generation)) / s.chi_n <
                    1.4 + 2 / (static_cast<double>(s.n) + 1);
  s.pc = (1 - s.cc) * s.pc + (hsig ? std::sqrt(s.cc * (2 - s.cc) * s.mueff) : 0.0) * yw;
  Eigen::MatrixXd rank_mu = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < s.mu; ++i) rank_mu += s.weights[i] * y.col(i) * y.col(i).transpose();
  s.C = (1 - s.c1 - s.cmu) * s.C + s.c1 * (s.pc * s.pc.transpose() + (hsig ? 0.0 : s.cc * (2 - s.cc)) * s.C) + s.cmu * rank_mu;
  s.sigma *= std::exp((s.cs / s.damps) * (ps_norm / s.chi_n - 1));
  s.decompose();
  s.mean_out.assign(s.mean.data(), s.mean.data() + n);
}

}  // namespace lptn::search
