// Particle storage: one array per field (structure of arrays), free of global state.
#pragma once

#include "sluice/core/parallel.hpp"
#include <array>
#include <cstdint>
#include <numeric>
#include <vector>

namespace sluice {

enum class Kind : std::uint8_t { fluid = 0, wall = 1 };

template <int Dim>
struct Particles {
  static constexpr int dim = Dim;

  // State.
  std::array<std::vector<double>, Dim> position;
  std::array<std::vector<double>, Dim> velocity;
  std::vector<double> density;
  std::vector<Kind> kind;
  std::vector<std::uint32_t> id;  // stable identity; the arrays are reordered by cell

  // Rates from the last force evaluation.
  std::array<std::vector<double>, Dim> acceleration;
  std::vector<double> density_rate;

  // State at the start of a step (multi-stage integrators).
  std::array<std::vector<double>, Dim> position_start;
  std::array<std::vector<double>, Dim> velocity_start;
  std::vector<double> density_start;

  // Set when a particle was put back from inside a wall; its density is re-interpolated
  // from its neighbours at the next force evaluation.
  std::vector<std::uint8_t> needs_density_repair;

  [[nodiscard]] std::size_t size() const { return density.size(); }

  void resize(std::size_t n) {
    for (auto* fields : {&position, &velocity, &acceleration, &position_start, &velocity_start})
      for (auto& f : *fields) f.resize(n, 0.0);
    for (auto* f : {&density, &density_rate, &density_start}) f->resize(n, 0.0);
    kind.resize(n, Kind::fluid);
    id.resize(n, 0);
    needs_density_repair.resize(n, 0);
  }

  // Appends a particle at rest while a set is being built. Only the state fields grow (keeping the
  // set-up's peak memory low); call resize(size()) before rates or step-start fields are used.
  void add(const std::array<double, Dim>& x, Kind k, double rho) {
    const std::size_t n = size();
    for (int d = 0; d < Dim; ++d) {
      position[d].push_back(x[d]);
      velocity[d].push_back(0.0);
    }
    density.push_back(rho);
    kind.push_back(k);
    id.push_back(static_cast<std::uint32_t>(n));
    needs_density_repair.push_back(0);
  }

  [[nodiscard]] bool is_fluid(std::size_t i) const { return kind[i] == Kind::fluid; }

  // Reorders the fields so that new index k holds what old index order[k] held. Rates are not
  // reordered (they are recomputed after every reordering); the step-start state only when asked
  // (during a multi-stage step). `scratch` avoids an allocation per call.
  void permute(const std::vector<std::uint32_t>& order, std::vector<double>& scratch, bool with_step_start,
               int threads) {
    const long n = static_cast<long>(size());
    scratch.resize(static_cast<std::size_t>(n));
    kind_scratch_.resize(static_cast<std::size_t>(n));
    id_scratch_.resize(static_cast<std::size_t>(n));
    repair_scratch_.resize(static_cast<std::size_t>(n));
    std::array<std::vector<double>*, 4 * Dim + 2> fields{};
    std::size_t count = 0;
    for (auto& f : position) fields[count++] = &f;
    for (auto& f : velocity) fields[count++] = &f;
    fields[count++] = &density;
    if (with_step_start) {
      for (auto& f : position_start) fields[count++] = &f;
      for (auto& f : velocity_start) fields[count++] = &f;
      fields[count++] = &density_start;
    }
    const std::uint32_t* __restrict from = order.data();
    // One parallel region for all the fields (a region per field cost more than the copies on two
    // threads). The double fields go through `scratch` one after another; each thread copies the same
    // static share of every field, and one thread swaps between fields.
#pragma omp parallel num_threads(threads) if (n >= light_loop_parallel_threshold)
    {
#pragma omp for schedule(static) nowait
      for (long k = 0; k < n; ++k) {
        kind_scratch_[k] = kind[from[k]];
        id_scratch_[k] = id[from[k]];
        repair_scratch_[k] = needs_density_repair[from[k]];
      }
      for (std::size_t f = 0; f < count; ++f) {
        std::vector<double>* const field = fields[f];
        const double* __restrict in = field->data();
        double* __restrict out = scratch.data();
#pragma omp for schedule(static)
        for (long k = 0; k < n; ++k) out[k] = in[from[k]];
#pragma omp single
        field->swap(scratch);
      }
    }
    kind.swap(kind_scratch_);
    id.swap(id_scratch_);
    needs_density_repair.swap(repair_scratch_);
  }

 private:
  std::vector<Kind> kind_scratch_;
  std::vector<std::uint32_t> id_scratch_;
  std::vector<std::uint8_t> repair_scratch_;
};

}  // namespace sluice
