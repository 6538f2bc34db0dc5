// The particles of a run spread over several processes (domain decomposition).
//
// Space is cut into one box per process by recursive coordinate bisection (Communicator::partition,
// Zoltan's RCB), weighted by the cost of the particles (a wall particle counts 0.1 of a fluid one: wall_weight); a process owns the particles inside its box. Every
// force evaluation starts with
//   1. the ghosts of the last evaluation dropped (strip_ghosts),
//   2. a new partition if the heaviest process holds more than `imbalance_limit` times the mean,
//   3. migration: owned particles that left the box go to the process whose box they are in, with
//      their state and the fields the integrator carries through the evaluation (its step-start
//      state, the leapfrog's rates),
//   4. ghosts: every owned particle within `halo` of another process's box is sent to it; the
//      receiver appends copies of the fields the pair loops read (field_role::halo).
// The evaluation then bins and reorders owned particles and ghosts together, and computes every
// particle's sums: an owned particle's neighbours within the halo width are all present, so its sums
// are complete, pairs across a boundary being computed on both sides (a ghost's own sums are
// incomplete and thrown away). A stage that changes a field later stages read for the ghosts too (the
// Shepard filter's densities, the wall densities) is followed by refresh(), which sends the owners'
// new values again. The ghosts stay until the next evaluation, so that the step's update may run over
// all particles; Solver::finish_step drops them, after which the process holds its owned particles
// only, as one process does (Particles::owned() == size()).
//
// Outputs are gathered to the root process (gather()), in particle-id order.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "sluice/core/communicator.hpp"
#include "sluice/core/particles.hpp"

namespace sluice {

template <int Dim>
class Distribution {
 public:
  // `halo`: how far from its box a process must see other processes' particles (the kernel support,
  // more where a stage reads further: mDBC's wall particles read the water around their ghost nodes).
  // `skin`: how much further ghosts are taken, so that they can serve a second evaluation of the
  // same step (before_evaluation).
  Distribution(const Communicator& comm, double halo, double skin, double imbalance_limit = 1.1)
      : comm_(comm), rank_(comm.rank()), halo_(halo), skin_(skin), imbalance_limit_(imbalance_limit) {}

  [[nodiscard]] const Communicator& comm() const { return comm_; }
  [[nodiscard]] const std::vector<DomainBox>& boxes() const { return boxes_; }
  [[nodiscard]] bool has_ghosts() const { return built_; }
  [[nodiscard]] std::size_t ghosts() const { return ghosts_; }
  // 1 for a ghost, by particle index (during an evaluation; empty between evaluations).
  [[nodiscard]] const std::vector<std::uint8_t>& ghost_mask() const { return ghost_; }
  [[nodiscard]] std::int64_t repartitions() const { return repartitions_; }
  [[nodiscard]] std::int64_t migrated() const { return migrated_; }
  // Ghosts made so far (summed over the builds), and the builds.
  [[nodiscard]] double ghosts_made() const { return ghosts_made_; }
  [[nodiscard]] std::int64_t ghost_builds() const { return builds_; }
  // Evaluations that kept the ghosts of the one before (refreshing their fields).
  [[nodiscard]] std::int64_t ghosts_reused() const { return reused_; }
  // Communication of the particle exchanges so far (migration, ghosts, refreshes): bytes this process
  // sent to others, and seconds it spent in the exchanges (waiting for the others included).
  [[nodiscard]] double bytes_sent() const { return bytes_sent_; }
  [[nodiscard]] double exchange_seconds() const { return exchange_seconds_; }

  // The pair loop's cost of a wall particle against a fluid one. Wall-wall pairs are skipped, and
  // most wall particles lie deeper in the wall than the water's reach: measured on SPHERIC test 2
  // (3D, dx = 0.03 m, 2 processes), 5346 fluid + 28162 wall particles cost 12.2 % of the run's CPU
  // time in the pair loop, 19008 + 14292 cost 35.8 %, so a wall particle costs 0.05 of a fluid one;
  // 0.1 allows for walls with more water against them (a 2D tank's floor).
  static constexpr double wall_weight = 0.1;
  // A set's load: what the boxes balance, in fluid particles.
  static double load(const Particles<Dim>& p) {
    double w = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) w += p.is_fluid(i) ? 1.0 : wall_weight;
    return w;
  }

  // Cuts space for the full set of particles that every process holds alike (a new case, or a
  // checkpoint), and keeps this process's share. Particle ids are kept.
  void distribute(Particles<Dim>& all) {
    const std::size_t n = all.size();
    const auto ranks = static_cast<std::size_t>(comm_.size()), me = static_cast<std::size_t>(comm_.rank());
    // Each process hands the partitioner its block of the (identical) full set.
    repartition(all, n * me / ranks, n * (me + 1) / ranks);
    std::vector<std::uint8_t> keep(n);
    for (std::size_t i = 0; i < n; ++i) keep[i] = owner(all, i) == rank_;
    compact(all, keep);
  }

  // Steps 1-4 above. `also` are the roles of the fields that move with the particles besides the
  // state (field_role::step_start, rates_start during a step).
  //
  // Within a step whose first evaluation built the ghosts (the predictor-corrector's second), the
  // ghosts are kept and only their fields refreshed, if no owned particle has moved more than half
  // the skin since (`moved`: the largest displacement on this process; the ghosts were taken from
  // `skin` beyond the halo): then a particle that came within the halo of another process's box
  // from outside was within halo + skin of it before, and is a ghost there already.
  void before_evaluation(Particles<Dim>& p, unsigned also, double moved = std::numeric_limits<double>::infinity()) {
    // Every process takes part in the decision (a process without particles has no ghosts either).
    const double farthest = comm_.reducer().max(built_ ? moved : std::numeric_limits<double>::infinity());
    if (farthest <= 0.5 * skin_) {
      refresh(p, {"position", "velocity", "density"});
      ++reused_;
      return;
    }
    strip_ghosts(p);
    const Reducer& all = comm_.reducer();
    const double owned = load(p);
    const double most = all.max(owned), mean = all.sum(owned) / comm_.size();
    if (most > imbalance_limit_ * mean) {
      repartition(p, 0, p.size());
      ++repartitions_;
    }
    migrate(p, also);
    add_ghosts(p);
  }

  // The evaluation reordered the particles: new index k holds what old index order[k] held.
  void reordered(const std::vector<std::uint32_t>& order) {
    if (!has_ghosts()) return;
    const std::size_t n = order.size();
    inverse_.resize(n);
    for (std::size_t k = 0; k < n; ++k) inverse_[order[k]] = static_cast<std::uint32_t>(k);
    std::vector<std::uint8_t> moved(n);
    for (std::size_t k = 0; k < n; ++k) moved[k] = ghost_[order[k]];
    ghost_.swap(moved);
    for (auto* lists : {&send_, &slots_})
      for (auto& list : *lists)
        for (auto& i : list) i = inverse_[i];
  }

  // Sends the owners' current values of the named fields to their ghosts.
  void refresh(Particles<Dim>& p, std::initializer_list<std::string_view> names) {
    std::vector<std::string> out(static_cast<std::size_t>(comm_.size()));
    for (std::size_t r = 0; r < out.size(); ++r)
      Particles<Dim>::fields(p, [&](const FieldSpec& info, auto& field) {
        if (named(info, names)) Particles<Dim>::components(field, [&](auto& c) { put(out[r], c, send_[r]); });
      });
    const std::vector<std::string> in = exchange(out);
    for (std::size_t r = 0; r < in.size(); ++r) {
      std::size_t at = 0;
      Particles<Dim>::fields(p, [&](const FieldSpec& info, auto& field) {
        if (named(info, names)) Particles<Dim>::components(field, [&](auto& c) { get(in[r], at, c, slots_[r]); });
      });
    }
  }
  // The same for an array indexed by particle (the shift's position divergence).
  void refresh(std::vector<double>& values) {
    std::vector<std::string> out(static_cast<std::size_t>(comm_.size()));
    for (std::size_t r = 0; r < out.size(); ++r) put(out[r], values, send_[r]);
    const std::vector<std::string> in = exchange(out);
    for (std::size_t r = 0; r < in.size(); ++r) {
      std::size_t at = 0;
      get(in[r], at, values, slots_[r]);
    }
  }

  // Drops the ghosts (every field, keeping the owned particles' order).
  // Returns which particles were kept (1) by index before the drop (empty when there were no ghosts),
  // for whoever indexes them too (the cell grid).
  std::vector<std::uint8_t> strip_ghosts(Particles<Dim>& p) {
    if (!has_ghosts()) return {};
    std::vector<std::uint8_t> keep;
    keep.swap(ghost_);
    for (auto& k : keep) k = !k;
    compact(p, keep);
    ghosts_ = 0;
    built_ = false;
    for (auto* lists : {&send_, &slots_})
      for (auto& list : *lists) list.clear();
    return keep;
  }

  // Every process's owned particles (the fields with any of `roles`, which must be fields every run
  // uses: the state, checkpoint, frame and carried fields), on the root in particle-id order; an
  // empty set on the other processes. Call between evaluations (no ghosts).
  [[nodiscard]] Particles<Dim> gather(const Particles<Dim>& p, unsigned roles) const {
    std::string part;
    put_count(part, p.size());
    std::vector<std::uint32_t> all_rows(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) all_rows[i] = static_cast<std::uint32_t>(i);
    Particles<Dim>::fields(p, [&](const FieldSpec& info, const auto& field) {
      if (info.has(roles)) Particles<Dim>::components(field, [&](const auto& c) { put(part, c, all_rows); });
    });
    const std::vector<std::string> parts = comm_.gather(part);
    Particles<Dim> out;
    if (!comm_.is_root()) return out;
    std::size_t total = 0;
    for (const std::string& s : parts) total += get_count(s);
    // Every field of the gathered set is sized (zero where not gathered), as a loaded set is.
    out.resize(total);
    std::size_t first = 0;
    for (const std::string& s : parts) {
      const std::size_t count = get_count(s);
      std::vector<std::uint32_t> rows(count);
      for (std::size_t k = 0; k < count; ++k) rows[k] = static_cast<std::uint32_t>(first + k);
      std::size_t at = sizeof(std::uint64_t);
      Particles<Dim>::fields(out, [&](const FieldSpec& info, auto& field) {
        if (info.has(roles)) Particles<Dim>::components(field, [&](auto& c) { get(s, at, c, rows); });
      });
      first += count;
    }
    std::vector<std::uint32_t> by_id(total);
    for (std::size_t k = 0; k < total; ++k) by_id[k] = static_cast<std::uint32_t>(k);
    std::sort(by_id.begin(), by_id.end(), [&](std::uint32_t a, std::uint32_t b) { return out.id[a] < out.id[b]; });
    std::vector<double> scratch;
    out.reorder(by_id, scratch, ~0u, 1);
    return out;
  }

  // The process whose box holds particle i (this process's for a particle in none: not finite).
  [[nodiscard]] int owner(const Particles<Dim>& p, std::size_t i) const {
    const int me = rank_;
    for (std::size_t r = 0; r < boxes_.size(); ++r) {
      bool inside = true;
      for (int d = 0; d < Dim; ++d) {
        const double x = p.position[d][i];
        inside = inside && boxes_[r].lower[d] <= x && x < boxes_[r].upper[d];
      }
      if (inside) return static_cast<int>(r);
    }
    return me;
  }

 private:
  std::vector<std::string> exchange(const std::vector<std::string>& out) {
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t r = 0; r < out.size(); ++r)
      if (r != static_cast<std::size_t>(comm_.rank())) bytes_sent_ += static_cast<double>(out[r].size());
    std::vector<std::string> in = comm_.exchange(out);
    exchange_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return in;
  }

  static bool named(const FieldSpec& info, std::initializer_list<std::string_view> names) {
    return std::find(names.begin(), names.end(), info.name) != names.end();
  }

  void repartition(const Particles<Dim>& p, std::size_t begin, std::size_t end) {
    std::vector<std::array<double, 3>> points(end - begin);
    for (std::size_t i = begin; i < end; ++i)
      for (int d = 0; d < Dim; ++d) {
        const double x = p.position[d][i];
        points[i - begin][static_cast<std::size_t>(d)] = std::isfinite(x) ? x : 0.0;
      }
    // Weighted by cost (wall_weight).
    std::vector<double> weights(points.size(), 1.0);
    for (std::size_t i = begin; i < end; ++i)
      if (!p.is_fluid(i)) weights[i - begin] = wall_weight;
    boxes_ = comm_.partition(Dim, points, weights);
    if (boxes_.size() != static_cast<std::size_t>(comm_.size()))
      throw std::logic_error("the partition has not one box per process");
  }

  // Owned particles outside this process's box go to the process whose box they are in.
  void migrate(Particles<Dim>& p, unsigned also) {
    const unsigned roles = field_role::state | also;
    const auto ranks = static_cast<std::size_t>(comm_.size());
    std::vector<std::vector<std::uint32_t>> leaving(ranks);
    std::vector<std::uint8_t> keep(p.size(), 1);
    for (std::size_t i = 0; i < p.size(); ++i) {
      const int r = owner(p, i);
      if (r == rank_) continue;
      leaving[static_cast<std::size_t>(r)].push_back(static_cast<std::uint32_t>(i));
      keep[i] = 0;
    }
    std::vector<std::string> out(ranks);
    for (std::size_t r = 0; r < ranks; ++r) {
      put_count(out[r], leaving[r].size());
      Particles<Dim>::fields(p, [&](const FieldSpec& info, auto& field) {
        if (info.has(roles)) Particles<Dim>::components(field, [&](auto& c) { put(out[r], c, leaving[r]); });
      });
    }
    const std::vector<std::string> in = exchange(out);
    std::size_t arriving = 0;
    for (std::size_t r = 0; r < ranks; ++r)
      if (r != static_cast<std::size_t>(comm_.rank())) arriving += get_count(in[r]);
    migrated_ += static_cast<std::int64_t>(p.size() - static_cast<std::size_t>(std::count(keep.begin(), keep.end(), 1)));
    compact(p, keep);
    append(p, in, roles, arriving, nullptr);
  }

  // Copies of other processes' particles within the halo of this process's box.
  void add_ghosts(Particles<Dim>& p) {
    const auto ranks = static_cast<std::size_t>(comm_.size());
    const auto me = static_cast<std::size_t>(comm_.rank());
    send_.assign(ranks, {});
    slots_.assign(ranks, {});
    const double halo2 = (halo_ + skin_) * (halo_ + skin_);
    for (std::size_t i = 0; i < p.size(); ++i)
      for (std::size_t r = 0; r < ranks; ++r) {
        if (r == me) continue;
        double d2 = 0.0;
        for (int d = 0; d < Dim; ++d) {
          const double x = p.position[d][i];
          const double below = boxes_[r].lower[d] - x, above = x - boxes_[r].upper[d];
          const double gap = std::max({below, above, 0.0});
          d2 += gap * gap;
        }
        if (d2 < halo2) send_[r].push_back(static_cast<std::uint32_t>(i));
      }
    std::vector<std::string> out(ranks);
    for (std::size_t r = 0; r < ranks; ++r) {
      put_count(out[r], send_[r].size());
      Particles<Dim>::fields(p, [&](const FieldSpec& info, auto& field) {
        if (info.has(field_role::halo)) Particles<Dim>::components(field, [&](auto& c) { put(out[r], c, send_[r]); });
      });
    }
    const std::vector<std::string> in = exchange(out);
    std::size_t arriving = 0;
    for (std::size_t r = 0; r < ranks; ++r)
      if (r != me) arriving += get_count(in[r]);
    const std::size_t owned = p.size();
    ghost_.assign(owned + arriving, 0);
    std::fill(ghost_.begin() + static_cast<long>(owned), ghost_.end(), 1);
    ghosts_ = arriving;
    ghosts_made_ += static_cast<double>(arriving);
    ++builds_;
    built_ = true;
    append(p, in, field_role::halo, arriving, &slots_);
  }

  // Appends the particles of every other process's message (fields with `roles`; the others zero);
  // records each one's new indices in (*slots)[r] when asked.
  void append(Particles<Dim>& p, const std::vector<std::string>& in, unsigned roles, std::size_t arriving,
              std::vector<std::vector<std::uint32_t>>* slots) {
    const std::size_t before = p.size();
    grow(p, before + arriving);
    std::size_t first = before;
    for (std::size_t r = 0; r < in.size(); ++r) {
      if (r == static_cast<std::size_t>(comm_.rank())) continue;
      const std::size_t count = get_count(in[r]);
      std::vector<std::uint32_t> rows(count);
      for (std::size_t k = 0; k < count; ++k) rows[k] = static_cast<std::uint32_t>(first + k);
      std::size_t at = sizeof(std::uint64_t);
      Particles<Dim>::fields(p, [&](const FieldSpec& info, auto& field) {
        if (info.has(roles)) Particles<Dim>::components(field, [&](auto& c) { get(in[r], at, c, rows); });
      });
      if (slots != nullptr) (*slots)[r] = std::move(rows);
      first += count;
    }
  }

  // Every field in use (of the particle count: fields a run does not use stay empty) to n entries.
  static void grow(Particles<Dim>& p, std::size_t n) {
    const std::size_t before = p.size();
    Particles<Dim>::fields(p, [&](const FieldSpec&, auto& field) {
      Particles<Dim>::components(field, [&](auto& c) {
        if (c.size() == before) c.resize(n);
      });
    });
  }

  // Keeps the particles with keep[i] != 0, in order, in every field in use.
  static void compact(Particles<Dim>& p, const std::vector<std::uint8_t>& keep) {
    const std::size_t n = p.size();
    // The kept rows, once; then each field is a gather (no branch per element and field).
    std::vector<std::uint32_t> rows;
    rows.reserve(n);
    for (std::size_t i = 0; i < n; ++i)
      if (keep[i]) rows.push_back(static_cast<std::uint32_t>(i));
    if (rows.size() == n) return;
    Particles<Dim>::fields(p, [&](const FieldSpec&, auto& field) {
      Particles<Dim>::components(field, [&](auto& c) {
        if (c.size() != n) return;
        auto* __restrict data = c.data();
        const std::uint32_t* __restrict from = rows.data();
        // In place: rows[k] >= k, so a row is read before anything overwrites it.
        for (std::size_t k = 0; k < rows.size(); ++k) data[k] = data[from[k]];
        c.resize(rows.size());
      });
    });
  }

  static void put_count(std::string& out, std::size_t count) {
    const auto c = static_cast<std::uint64_t>(count);
    out.append(reinterpret_cast<const char*>(&c), sizeof c);
  }
  static std::size_t get_count(const std::string& in) {
    std::uint64_t c = 0;
    if (in.size() < sizeof c) throw std::runtime_error("a message between processes is cut short");
    std::memcpy(&c, in.data(), sizeof c);
    return static_cast<std::size_t>(c);
  }
  template <class T>
  static void put(std::string& out, const std::vector<T>& values, const std::vector<std::uint32_t>& rows) {
    const std::size_t at = out.size();
    out.resize(at + rows.size() * sizeof(T));
    char* to = out.data() + at;
    for (std::size_t k = 0; k < rows.size(); ++k) std::memcpy(to + k * sizeof(T), &values[rows[k]], sizeof(T));
  }
  template <class T>
  static void get(const std::string& in, std::size_t& at, std::vector<T>& values, const std::vector<std::uint32_t>& rows) {
    if (at + rows.size() * sizeof(T) > in.size()) throw std::runtime_error("a message between processes is cut short");
    const char* from = in.data() + at;
    for (std::size_t k = 0; k < rows.size(); ++k) std::memcpy(&values[rows[k]], from + k * sizeof(T), sizeof(T));
    at += rows.size() * sizeof(T);
  }

  const Communicator& comm_;
  int rank_;
  double halo_;
  double skin_;
  double imbalance_limit_;
  std::vector<DomainBox> boxes_;
  std::vector<std::uint8_t> ghost_;
  std::size_t ghosts_ = 0;
  bool built_ = false;  // the ghosts of this evaluation's step are in place (perhaps none)
  // send_[r]: the indices of this process's particles that are ghosts on process r; slots_[r]: the
  // indices of the ghosts process r owns, in the order r sends them.
  std::vector<std::vector<std::uint32_t>> send_, slots_;
  std::vector<std::uint32_t> inverse_;
  std::int64_t repartitions_ = 0;
  std::int64_t migrated_ = 0;
  std::int64_t reused_ = 0;
  std::int64_t builds_ = 0;
  double ghosts_made_ = 0.0;
  double bytes_sent_ = 0.0;
  double exchange_seconds_ = 0.0;
};

}  // namespace sluice
