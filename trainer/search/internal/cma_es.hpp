// CMA-ES, (mu/mu_w, lambda) with rank-one and rank-mu updates and cumulative step-size adaptation,
// after N. Hansen, "The CMA Evolution Strategy: A Tutorial" (arXiv:1604.00772), its default
// parameters. Ask-tell, so that a generation's points are scored together on every core.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

namespace lptn::search {

class CmaEs {
 public:
  // lambda 0: the tutorial's default 4 + floor(3 ln n).
  CmaEs(std::vector<double> mean, double sigma, std::uint64_t seed, int lambda = 0);
  ~CmaEs();

  int lambda() const;
  std::size_t dimension() const;
  // A generation's points, row-major lambda x n.
  std::vector<double> ask();
  // Their costs (lower is better), in ask()'s order.
  void tell(const std::vector<double>& costs);
  const std::vector<double>& mean() const;
  double sigma() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lptn::search
