// Particle storage: one array per field (structure of arrays), free of global state.
//
// Every field is declared once, in Particles::fields(), with what happens to it; storage growth,
// reordering, checkpoints and frames follow from that list (io/checkpoint.cpp and io/frames.cpp read
// and write it by name).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <vector>

#include "sluice/core/body_id.hpp"
#include "sluice/core/parallel.hpp"

namespace sluice {

enum class Kind : std::uint8_t { fluid = 0, wall = 1 };


// What happens to a field.
namespace field_role {
inline constexpr unsigned state = 1;       // the particle's state: grows with add(), moves with every reordering
inline constexpr unsigned step_start = 2;  // moves with a reordering during a multi-stage step only
inline constexpr unsigned checkpoint = 4;  // saved in checkpoints
inline constexpr unsigned halo = 8;        // read by the pair loop: what a neighbouring process must send
inline constexpr unsigned frame = 16;      // written in output frames, in registry order
// The rates a leapfrog step carries into the next (its a^n, D^n: integrate/integrators.hpp): saved in
// checkpoints while they are carried (Clock::rates_carried).
inline constexpr unsigned carried = 32;
inline constexpr unsigned rates_start = 64;  // moves with the reordering during a leapfrog step only
// Recomputed after every reordering that does not move it, which may use its storage as scratch.
inline constexpr unsigned recomputed = 128;
}  // namespace field_role

struct FieldSpec {
  std::string_view name;  // also a frame field's array name in .vtu frames
  std::string_view unit;  // "" when dimensionless
  unsigned roles;
  std::string_view short_name = {};  // a frame field's array name in .npz frames (x, v, rho: typed in NumPy)
  [[nodiscard]] bool has(unsigned role) const { return (roles & role) != 0; }
};

template <int Dim>
struct Particles {
  static constexpr int dim = Dim;
  template <class T>
  using Vector = std::array<std::vector<T>, Dim>;  // one array per component

  // State.
  Vector<double> position;
  Vector<double> velocity;
  std::vector<double> density;
  std::vector<Kind> kind;
  std::vector<std::uint32_t> id;  // stable identity; the arrays are reordered by cell
  std::vector<std::uint8_t> body;  // body_id: water, the tank, or a [[wall]]
  // Set when a particle was put back from inside a wall; its density is re-interpolated from its
  // neighbours at the next force evaluation.
  std::vector<std::uint8_t> needs_density_repair;

  // Rates from the last force evaluation. The reordering of an evaluation leaves them behind (they
  // are recomputed after it); between evaluations nothing reorders, so the leapfrog carries them from
  // one step into the next.
  Vector<double> acceleration;
  std::vector<double> density_rate;

  // State at the start of a step (multi-stage integrators; the instability guard goes back to it).
  Vector<double> position_start;
  Vector<double> velocity_start;
  std::vector<double> density_start;
  // The rates at the start of a leapfrog step, a^n and D^n, which its evaluation's reordering moves
  // (empty with the other integrators: Solver::init).
  Vector<double> acceleration_start;
  std::vector<double> density_rate_start;

  // The field registry: calls f(info, field) for every field, in a fixed order; `field` is a
  // std::vector<T> or a Vector<T>. Works on const and non-const particles.
  template <class Self, class F>
  static void fields(Self& p, F&& f) {
    using namespace field_role;
    f(FieldSpec{"position", "m", state | checkpoint | halo | frame, "x"}, p.position);
    f(FieldSpec{"velocity", "m/s", state | checkpoint | halo | frame, "v"}, p.velocity);
    f(FieldSpec{"density", "kg/m^3", state | checkpoint | halo | frame, "rho"}, p.density);
    f(FieldSpec{"kind", "", state | checkpoint | halo | frame, "kind"}, p.kind);
    f(FieldSpec{"id", "", state | checkpoint | halo | frame, "id"}, p.id);
    f(FieldSpec{"body", "", state | checkpoint | halo | frame, "body"}, p.body);
    f(FieldSpec{"needs_density_repair", "", state | checkpoint}, p.needs_density_repair);
    f(FieldSpec{"acceleration", "m/s^2", carried | recomputed}, p.acceleration);
    f(FieldSpec{"density_rate", "kg/m^3/s", carried | recomputed}, p.density_rate);
    f(FieldSpec{"position_start", "m", step_start}, p.position_start);
    f(FieldSpec{"velocity_start", "m/s", step_start}, p.velocity_start);
    f(FieldSpec{"density_start", "kg/m^3", step_start}, p.density_start);
    f(FieldSpec{"acceleration_start", "m/s^2", rates_start}, p.acceleration_start);
    f(FieldSpec{"density_rate_start", "kg/m^3/s", rates_start}, p.density_rate_start);
  }

  // Calls g(component) for each component array of a field (one for a scalar field).
  template <class Field, class G>
  static void components(Field& field, G&& g) {
    using Element = typename std::remove_cvref_t<Field>::value_type;
    if constexpr (std::is_arithmetic_v<Element> || std::is_enum_v<Element>) g(field);
    else
      for (auto& c : field) g(c);
  }

  // With several processes, each holds the particles it owns; during a force evaluation also ghosts,
  // copies of other processes' particles near its region, mixed in by the reordering and dropped
  // before the evaluation's results are used (solver/distribution.hpp). Outside an evaluation, all
  // of a process's particles are owned: owned() == size(). Global sums and maxima are over owned
  // particles, combined across processes by a Reducer (core/reduce.hpp).
  [[nodiscard]] std::size_t size() const { return density.size(); }
  [[nodiscard]] std::size_t owned() const { return size(); }
  [[nodiscard]] bool is_fluid(std::size_t i) const { return kind[i] == Kind::fluid; }

  void resize(std::size_t n) {
    fields(*this, [&](const FieldSpec&, auto& field) { components(field, [&](auto& c) { c.resize(n); }); });
  }

  // Appends a particle at rest while a set is being built. Only the state fields grow (keeping the
  // set-up's peak memory low); call resize(size()) before rates or step-start fields are used.
  // A wall particle is the tank's unless `in_body` says otherwise.
  void add(const std::array<double, Dim>& x, Kind k, double rho) {
    add(x, k, rho, k == Kind::wall ? body_id::tank : body_id::water);
  }
  void add(const std::array<double, Dim>& x, Kind k, double rho, std::uint8_t in_body) {
    const std::size_t n = size();
    fields(*this, [&](const FieldSpec& info, auto& field) {
      if (info.has(field_role::state)) components(field, [](auto& c) { c.emplace_back(); });
    });
    for (int d = 0; d < Dim; ++d) position[d][n] = x[d];
    density[n] = rho;
    kind[n] = k;
    id[n] = static_cast<std::uint32_t>(n);
    body[n] = in_body;
  }

  // Keeps the state of the particles `keep` (ascending indices), renumbered 0..k-1 in that order;
  // the other fields are sized to match (and zero).
  void keep_only(const std::vector<std::uint32_t>& keep) {
    fields(*this, [&](const FieldSpec& info, auto& field) {
      components(field, [&](auto& c) {
        std::remove_reference_t<decltype(c)> kept(keep.size());
        if (info.has(field_role::state))
          for (std::size_t k = 0; k < keep.size(); ++k) kept[k] = c[keep[k]];
        c.swap(kept);
      });
    });
    for (std::size_t k = 0; k < keep.size(); ++k) id[k] = static_cast<std::uint32_t>(k);
  }

  // Removes the particles with gone[i] != 0 (outflow: Solver::finish_step), keeping the others in
  // their order with their ids; every field in use (of the particle count) is compacted alike, so that
  // step-start state and carried rates stay with their particles. Fields not in use stay empty.
  void erase(const std::vector<std::uint8_t>& gone) {
    const std::size_t n = size();
    fields(*this, [&](const FieldSpec&, auto& field) {
      components(field, [&](auto& c) {
        if (c.size() != n) return;
        std::size_t k = 0;
        for (std::size_t i = 0; i < n; ++i)
          if (gone[i] == 0) c[k++] = c[i];
        c.resize(k);
      });
    });
  }

  // Reorders the fields so that new index k holds what old index order[k] held: the state, and the
  // step-start state when asked (during a multi-stage step). Rates are not reordered (they are
  // recomputed after every reordering).
  void permute(const std::vector<std::uint32_t>& order, std::vector<double>& scratch, bool with_step_start,
               int threads) {
    reorder(order, scratch, with_step_start ? field_role::step_start : 0u, threads);
  }

  // The same for the state and the fields with any of the roles `also` (field_role::step_start,
  // rates_start). The fields this reordering leaves behind that are recomputed after it
  // (field_role::recomputed) hold the double fields in turn, their contents then unspecified; when
  // none is in use, `scratch` does (no allocation per call).
  //
  // The copies run in one parallel region, each thread copying its static share of every field. A
  // field's old array can take another field's copy only once every thread has finished reading it,
  // so the copies run in rounds separated by barriers: as many fields per round as there are spare
  // arrays of their type (on two threads a barrier costs about as much as copying a field of 80k
  // doubles). The arrays are handed round afterwards by swaps, without copying.
  void reorder(const std::vector<std::uint32_t>& order, std::vector<double>& scratch, unsigned also, int threads) {
    const long n = static_cast<long>(size());
    const auto un = static_cast<std::size_t>(n);
    std::get<std::vector<Kind>>(scratch_).resize(un);
    std::get<std::vector<std::uint32_t>>(scratch_).resize(un);
    std::get<std::vector<std::uint8_t>>(scratch_).resize(un);
    const unsigned moved = field_role::state | also;

    // The spare arrays of each type: the array that holds it (swapped into place afterwards), its
    // data, and the first round in which it is free. The fields recomputed after the reordering are
    // the spare doubles; `scratch` is used (and sized) only when there are none, so that it takes no
    // memory in a run (8 bytes per particle).
    std::tuple<Spares<double>, Spares<Kind>, Spares<std::uint32_t>, Spares<std::uint8_t>> spares;
    fields(*this, [&](const FieldSpec& info, auto& field) {
      if (info.has(moved) || !info.has(field_role::recomputed)) return;
      components(field, [&](auto& c) {
        using T = typename std::remove_reference_t<decltype(c)>::value_type;
        if (c.size() == un) std::get<Spares<T>>(spares).push_back({&c, c.data(), 0});
      });
    });
    if (std::get<Spares<double>>(spares).empty()) {
      scratch.resize(un);
      std::get<Spares<double>>(spares).push_back({&scratch, scratch.data(), 0});
    }
    std::apply([&](auto&... s) { (add_scratch(s), ...); }, spares);
    // The plan: each moved component is copied into the spare array of its type that is free first;
    // its own array becomes free in the next round.
    std::vector<Copy> copies;
    std::vector<std::function<void()>> swaps;
    int rounds = 0;
    fields(*this, [&](const FieldSpec& info, auto& field) {
      if (!info.has(moved)) return;
      components(field, [&](auto& c) {
        using T = typename std::remove_reference_t<decltype(c)>::value_type;
        Spares<T>& free = std::get<Spares<T>>(spares);
        const auto first = std::min_element(free.begin(), free.end(),
                                            [](const auto& a, const auto& b) { return a.round < b.round; });
        const Spare<T> spare = *first;
        free.erase(first);
        copies.push_back({&copy_share<T>, c.data(), spare.data, spare.round});
        swaps.emplace_back([holder = spare.holder, &c] { holder->swap(c); });
        free.push_back({spare.holder, c.data(), spare.round + 1});
        rounds = std::max(rounds, spare.round + 1);
      });
    });
    const std::uint32_t* from = order.data();
    parallel::in_team(threads, n >= parallel::light_loop_threshold, [&](const parallel::Team& team) {
      const long begin = n * team.index() / team.size(), end = n * (team.index() + 1) / team.size();
      for (int round = 0; round < rounds; ++round) {
        if (round > 0) team.barrier();
        for (const Copy& copy : copies)
          if (copy.round == round) copy.run(copy.in, copy.out, from, begin, end);
      }
    });
    for (const auto& swap : swaps) swap();
  }

 private:
  template <class T>
  struct Spare {
    std::vector<T>* holder;
    T* data;
    int round;
  };
  template <class T>
  using Spares = std::vector<Spare<T>>;
  struct Copy {
    void (*run)(const void* in, void* out, const std::uint32_t* from, long begin, long end);
    const void* in;
    void* out;
    int round;
  };
  template <class T>
  static void copy_share(const void* in, void* out, const std::uint32_t* from, long begin, long end) {
    const T* __restrict src = static_cast<const T*>(in);
    T* __restrict dst = static_cast<T*>(out);
    for (long k = begin; k < end; ++k) dst[k] = src[from[k]];
  }
  template <class T>
  void add_scratch(Spares<T>& s) {
    if constexpr (!std::is_same_v<T, double>) {
      std::vector<T>& v = std::get<std::vector<T>>(scratch_);
      s.push_back({&v, v.data(), 0});
    }
  }

  std::tuple<std::vector<Kind>, std::vector<std::uint32_t>, std::vector<std::uint8_t>> scratch_;
};

}  // namespace sluice
