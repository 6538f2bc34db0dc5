#include "sluice/mpi/mpi_communicator.hpp"

#include <fmt/format.h>
#include <mpi.h>
#include <unistd.h>
#include <zoltan.h>
#include <zoltan_partition_tree.h>

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <limits>
#include <mutex>
#include <new>
#include <numeric>
#include <optional>
#include <stdexcept>

// MPI calls are not checked for errors: MPI_COMM_WORLD's handler (and so our duplicate's) is
// MPI_ERRORS_ARE_FATAL, which stops every process on the first error with MPI's own message.

namespace sluice {
namespace {

// MPI counts elements in int.
constexpr std::uint64_t max_count = INT_MAX;

bool mpi_finalized() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  return finalized != 0;
}

// The maximum and minimum of two parts whatever the order MPI combines them in (it may combine them
// in different orders on different processes): a NaN wins (the result is the one quiet NaN), and so
// does +0 over -0 for the maximum and -0 over +0 for the minimum, so that every process gets the
// same bits.
double larger(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<double>::quiet_NaN();
  if (a == b) return std::signbit(a) ? b : a;
  return a > b ? a : b;
}

double smaller(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<double>::quiet_NaN();
  if (a == b) return std::signbit(a) ? a : b;
  return a < b ? a : b;
}

void max_op(void* in, void* inout, int* length, MPI_Datatype*) {
  const auto* a = static_cast<const double*>(in);
  auto* b = static_cast<double*>(inout);
  for (int i = 0; i < *length; ++i) b[i] = larger(a[i], b[i]);
}

void min_op(void* in, void* inout, int* length, MPI_Datatype*) {
  const auto* a = static_cast<const double*>(in);
  auto* b = static_cast<double*>(inout);
  for (int i = 0; i < *length; ++i) b[i] = smaller(a[i], b[i]);
}

// The first process's message on every process, or nothing when no process has one. A process that
// threw alone would leave the others waiting for it in their next collective call.
std::optional<std::string> first_error(MPI_Comm comm, int rank, int size, const std::string& mine) {
  const int candidate = mine.empty() ? size : rank;
  int first = size;
  MPI_Allreduce(&candidate, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == size) return std::nullopt;
  std::uint64_t length = mine.size();
  MPI_Bcast(&length, 1, MPI_UINT64_T, first, comm);
  std::string message = rank == first ? mine : std::string(length, '\0');
  MPI_Bcast(message.data(), static_cast<int>(length), MPI_CHAR, first, comm);
  return message;
}

// The failure of the first process that reported one (Communicator::fail), on every process.
// `mine` is this process's, or null.
Failure first_failure(MPI_Comm comm, int rank, int size, const Failure* mine) {
  const int candidate = mine != nullptr ? rank : size;
  int first = size;
  MPI_Allreduce(&candidate, &first, 1, MPI_INT, MPI_MIN, comm);
  Failure f;
  f.process = first;
  f.processes = size;
  std::int64_t head[2] = {0, 0};  // kind, message length
  if (rank == first) {
    f.kind = mine->kind;
    f.message = mine->message;
    head[0] = f.kind;
    head[1] = static_cast<std::int64_t>(std::min<std::size_t>(f.message.size(), max_count));
  }
  MPI_Bcast(head, 2, MPI_INT64_T, first, comm);
  f.kind = static_cast<int>(head[0]);
  f.message.resize(static_cast<std::size_t>(head[1]));
  MPI_Bcast(f.message.data(), static_cast<int>(head[1]), MPI_CHAR, first, comm);
  return f;
}

// What every collective call does first: learn whether a process has failed (Communicator::fail, which
// takes part in this reduction with 1), and if one has, throw its Failure instead of going on.
void check_failures(MPI_Comm comm, int rank, int size) {
  const int mine = 0;
  int any = 0;
  MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, comm);
  if (any != 0) throw ProcessFailure(first_failure(comm, rank, size, nullptr));
}

class MpiReducer final : public Reducer {
 public:
  MpiReducer(MPI_Comm comm, int rank, int size) : comm_(comm), rank_(rank), size_(size) {
    MPI_Op_create(&max_op, /*commute=*/1, &max_);
    MPI_Op_create(&min_op, /*commute=*/1, &min_);
  }
  ~MpiReducer() override {
    if (mpi_finalized()) return;
    MPI_Op_free(&max_);
    MPI_Op_free(&min_);
  }
  MpiReducer(const MpiReducer&) = delete;
  MpiReducer& operator=(const MpiReducer&) = delete;

  // Vectors of different lengths would make MPI read past the shorter ones: check first, on all; and
  // that `copies` of them fit MPI's int counts.
  void check_equal_lengths(const char* what, std::size_t size, std::size_t copies) const {
    const auto length = static_cast<long long>(size);
    long long bounds[2] = {length, -length};
    MPI_Allreduce(MPI_IN_PLACE, bounds, 2, MPI_LONG_LONG, MPI_MIN, comm_);
    if (bounds[0] != -bounds[1])
      throw std::invalid_argument(fmt::format(
          "{}: vectors of {} to {} elements on the processes; expected the same length on all", what, bounds[0],
          -bounds[1]));
    if (size * copies > max_count)
      throw std::length_error(fmt::format("{}: vectors of {} elements from {} processes; MPI counts them in int, at "
                                          "most {}",
                                          what, size, copies, max_count));
  }

  // Every process adds all the parts in rank order (MPI_SUM would add them in an order of MPI's
  // choosing, which may differ between processes and runs, and so may the last bits).
  [[nodiscard]] double sum(double part) const override {
    check_failures(comm_, rank_, size_);
    std::vector<double> parts(static_cast<std::size_t>(size_));
    MPI_Allgather(&part, 1, MPI_DOUBLE, parts.data(), 1, MPI_DOUBLE, comm_);
    double total = parts[0];
    for (std::size_t r = 1; r < parts.size(); ++r) total += parts[r];
    return total;
  }

  [[nodiscard]] std::int64_t sum(std::int64_t part) const override {
    check_failures(comm_, rank_, size_);
    std::int64_t total = 0;
    MPI_Allreduce(&part, &total, 1, MPI_INT64_T, MPI_SUM, comm_);
    return total;
  }

  [[nodiscard]] double max(double part) const override {
    check_failures(comm_, rank_, size_);
    double result = part;
    MPI_Allreduce(&part, &result, 1, MPI_DOUBLE, max_, comm_);
    return result;
  }

  [[nodiscard]] double min(double part) const override {
    check_failures(comm_, rank_, size_);
    double result = part;
    MPI_Allreduce(&part, &result, 1, MPI_DOUBLE, min_, comm_);
    return result;
  }

  // Every process gathers every part and adds them in rank order, as sum(double) does.
  [[nodiscard]] std::vector<double> sum(std::vector<double> parts) const override {
    check_failures(comm_, rank_, size_);
    check_equal_lengths("sum", parts.size(), static_cast<std::size_t>(size_));
    std::vector<double> all(parts.size() * static_cast<std::size_t>(size_));
    MPI_Allgather(parts.data(), static_cast<int>(parts.size()), MPI_DOUBLE, all.data(), static_cast<int>(parts.size()),
                  MPI_DOUBLE, comm_);
    for (std::size_t k = 0; k < parts.size(); ++k) {
      double total = all[k];
      for (std::size_t r = 1; r < static_cast<std::size_t>(size_); ++r) total += all[r * parts.size() + k];
      parts[k] = total;
    }
    return parts;
  }

  [[nodiscard]] std::vector<double> max(std::vector<double> parts) const override {
    check_failures(comm_, rank_, size_);
    check_equal_lengths("max", parts.size(), 1);
    MPI_Allreduce(MPI_IN_PLACE, parts.data(), static_cast<int>(parts.size()), MPI_DOUBLE, max_, comm_);
    return parts;
  }

  // Every process learns every value and payload length, picks the same winner (NaN above every
  // number, ties to the lowest rank, +0 and -0 equal) and receives the winner's payload.
  [[nodiscard]] std::vector<double> payload_of_max(double value, std::vector<double> payload) const override {
    check_failures(comm_, rank_, size_);
    struct Entry {
      double value;
      std::uint64_t length;
    };
    const Entry mine{value, payload.size()};
    std::vector<Entry> entries(static_cast<std::size_t>(size_));
    constexpr int bytes = sizeof(Entry);
    MPI_Allgather(&mine, bytes, MPI_BYTE, entries.data(), bytes, MPI_BYTE, comm_);
    auto beats = [](double a, double b) { return std::isnan(b) ? false : std::isnan(a) || a > b; };
    int winner = 0;
    for (int r = 1; r < size_; ++r)
      if (beats(entries[static_cast<std::size_t>(r)].value, entries[static_cast<std::size_t>(winner)].value))
        winner = r;
    const std::uint64_t length = entries[static_cast<std::size_t>(winner)].length;
    if (length > max_count)
      throw std::length_error(
          fmt::format("payload_of_max: a payload of {} values; MPI counts them in int, at most {}", length, max_count));
    payload.resize(length);
    MPI_Bcast(payload.data(), static_cast<int>(length), MPI_DOUBLE, winner, comm_);
    return payload;
  }

 private:
  MPI_Comm comm_;
  int rank_;
  int size_;
  MPI_Op max_ = MPI_OP_NULL;
  MPI_Op min_ = MPI_OP_NULL;
};

MPI_Comm duplicate_world() {
  MPI_Comm comm = MPI_COMM_NULL;
  MPI_Comm_dup(MPI_COMM_WORLD, &comm);
  return comm;
}

int rank_of(MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return rank;
}

int size_of(MPI_Comm comm) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  return size;
}

// ---- Zoltan ----

// What the Zoltan callbacks read: this process's points, as objects with global ids (rank, index)
// and local ids (index).
struct ZoltanInput {
  const std::vector<std::array<double, 3>>* points = nullptr;
  std::vector<float> weights;
  int dimension = 3;
  ZOLTAN_ID_TYPE rank = 0;
};

int zoltan_object_count(void* data, int* error) {
  *error = ZOLTAN_OK;
  return static_cast<int>(static_cast<const ZoltanInput*>(data)->points->size());
}

void zoltan_objects(void* data, int, int, ZOLTAN_ID_PTR global_ids, ZOLTAN_ID_PTR local_ids, int weight_dim,
                    float* weights, int* error) {
  const auto& in = *static_cast<const ZoltanInput*>(data);
  for (std::size_t i = 0; i < in.points->size(); ++i) {
    global_ids[2 * i] = in.rank;
    global_ids[2 * i + 1] = static_cast<ZOLTAN_ID_TYPE>(i);
    local_ids[i] = static_cast<ZOLTAN_ID_TYPE>(i);
    if (weight_dim == 1) weights[i] = in.weights[i];
  }
  *error = ZOLTAN_OK;
}

int zoltan_dimension(void* data, int* error) {
  *error = ZOLTAN_OK;
  return static_cast<const ZoltanInput*>(data)->dimension;
}

void zoltan_coordinates(void* data, int, int local_id_size, int count, ZOLTAN_ID_PTR, ZOLTAN_ID_PTR local_ids,
                        int dimension, double* coordinates, int* error) {
  const auto& in = *static_cast<const ZoltanInput*>(data);
  for (int k = 0; k < count; ++k) {
    const auto& point = (*in.points)[local_ids[k * local_id_size]];
    for (int d = 0; d < dimension; ++d) coordinates[k * dimension + d] = point[static_cast<std::size_t>(d)];
  }
  *error = ZOLTAN_OK;
}

struct ZoltanDestroy {
  void operator()(Zoltan_Struct* zz) const { Zoltan_Destroy(&zz); }
};

void zoltan_check(int status, const char* what) {
  if (status != ZOLTAN_OK && status != ZOLTAN_WARN)
    throw std::runtime_error(fmt::format("Zoltan: {} failed (error code {})", what, status));
}

void set_zoltan_param(Zoltan_Struct* zz, const char* name, const std::string& value) {
  if (Zoltan_Set_Param(zz, name, value.c_str()) != ZOLTAN_OK)
    throw std::runtime_error(fmt::format("Zoltan: parameter {} = {} was refused", name, value));
}

// Zoltan_Initialize once per process (after MPI_Init, so it leaves MPI alone).
void initialize_zoltan() {
  static std::once_flag once;
  std::call_once(once, [] {
    float version = 0.0f;
    zoltan_check(Zoltan_Initialize(0, nullptr, &version), "Zoltan_Initialize");
  });
}

DomainBox all_of_space() {
  constexpr double inf = std::numeric_limits<double>::infinity();
  return {{-inf, -inf, -inf}, {inf, inf, inf}};
}

// Coordinates are at most 1e300 in magnitude. A cut beyond 1e307 is then one that Zoltan drew halfway
// between the points and DBL_MAX, where it puts the open faces (a side without points), and it
// stands for infinity.
constexpr double max_coordinate = 1e300;
constexpr double beyond_the_points = 1e307;

// Zoltan's boxes, made to tile space. Zoltan_RCB_Box walks Zoltan's tree of cuts from the root and
// overwrites a face with each cut on the way, without keeping the cut inside the faces set before:
// a cut outside its region (with AVERAGE_CUTS, the cut of a region whose points cannot be split is
// halfway to DBL_MAX) then reaches across other boxes, and boxes overlap. So each cut is read back
// from Zoltan's boxes and tree, and the boxes are rebuilt from the root with every cut kept inside
// its region. Rebuilding Zoltan's way must give Zoltan's boxes back, which checks the reading.
std::vector<DomainBox> tiling_boxes(Zoltan_Struct* z, int parts, int dimension) {
  const auto count = static_cast<std::size_t>(parts);
  std::vector<DomainBox> zoltan(count);
  for (std::size_t p = 0; p < count; ++p) {
    int box_dimension = 0;
    DomainBox& b = zoltan[p];
    zoltan_check(Zoltan_RCB_Box(z, static_cast<int>(p), &box_dimension, &b.lower[0], &b.lower[1], &b.lower[2],
                                &b.upper[0], &b.upper[1], &b.upper[2]),
                 "Zoltan_RCB_Box");
  }

  // The tree: nodes 1 to parts - 1, whose children are nodes (> 0) or parts (the part -child, <= 0).
  // Parts below a node's index are on its left, the others on its right.
  struct Node {
    int left = 0;
    int right = 0;
  };
  std::vector<Node> nodes(count);
  std::vector<bool> is_child(count, false);
  auto bad_tree = [](const std::string& what) {
    return std::logic_error("partition: Zoltan's tree of cuts " + what +
                            "; expected the tree that Zoltan_RCB_Box walks (is this another version of Zoltan?)");
  };
  for (int k = 1; k < parts; ++k) {
    int parent = 0, left = 0, right = 0;
    zoltan_check(Zoltan_RCB_Partition_Tree(z, k, &parent, &left, &right), "Zoltan_RCB_Partition_Tree");
    for (int child : {left, right}) {
      if (child >= parts || -child >= parts) throw bad_tree(fmt::format("has a child {} of node {}", child, k));
      if (child > 0) is_child[static_cast<std::size_t>(child)] = true;
    }
    nodes[static_cast<std::size_t>(k)] = {left, right};
  }
  int root = 0;
  for (int k = 1; k < parts; ++k)
    if (!is_child[static_cast<std::size_t>(k)]) {
      if (root != 0) throw bad_tree("has two roots");
      root = k;
    }
  if (root == 0) throw bad_tree("has no root");
  // The part at the far left or right end of a subtree.
  auto end_part = [&](int child, bool rightmost) {
    for (int steps = 0; child > 0 && steps < parts; ++steps) {
      const Node& node = nodes[static_cast<std::size_t>(child)];
      child = rightmost ? node.right : node.left;
    }
    if (child > 0) throw bad_tree("has a loop");
    return static_cast<std::size_t>(-child);
  };

  constexpr double inf = std::numeric_limits<double>::infinity();
  struct Pending {
    int child;
    DomainBox zoltan;  // the faces Zoltan_RCB_Box sets on the way to here
    DomainBox region;  // the faces kept inside each other
  };
  std::vector<Pending> pending{{root, {{-DBL_MAX, -DBL_MAX, -DBL_MAX}, {DBL_MAX, DBL_MAX, DBL_MAX}}, all_of_space()}};
  std::vector<DomainBox> rebuilt(count), boxes(count);
  std::vector<int> reached(count, 0);
  for (int visits = 0; !pending.empty(); ++visits) {
    if (visits > 2 * parts) throw bad_tree("has a loop");
    const Pending at = pending.back();
    pending.pop_back();
    if (at.child <= 0) {
      const auto p = static_cast<std::size_t>(-at.child);
      ++reached[p];
      rebuilt[p] = at.zoltan;
      boxes[p] = at.region;
      continue;
    }
    const Node& node = nodes[static_cast<std::size_t>(at.child)];
    // The first part right of the cut has the cut as its lower face in the cut's component, and its
    // region's other lower faces; the last part left of it has the cut as its upper face.
    const DomainBox& above = zoltan[end_part(node.right, false)];
    const DomainBox& below = zoltan[end_part(node.left, true)];
    std::size_t c = 3;
    for (std::size_t d = 0; d < 3 && c == 3; ++d)
      if (above.lower[d] != at.zoltan.lower[d] || below.upper[d] != at.zoltan.upper[d]) c = d;
    // No face moved: the cut is on both faces of a region of no width, and cutting there across any
    // such component gives the same boxes.
    for (std::size_t d = 0; d < 3 && c == 3; ++d)
      if (at.zoltan.lower[d] == at.zoltan.upper[d]) c = d;
    if (c == 3) throw bad_tree(fmt::format("has a cut of node {} on no face", at.child));
    const double cut = above.lower[c];
    Pending left{node.left, at.zoltan, at.region}, right{node.right, at.zoltan, at.region};
    left.zoltan.upper[c] = cut;
    right.zoltan.lower[c] = cut;
    if (c < static_cast<std::size_t>(dimension)) {
      const double kept = std::clamp(std::abs(cut) > beyond_the_points ? std::copysign(inf, cut) : cut,
                                     at.region.lower[c], at.region.upper[c]);
      left.region.upper[c] = kept;
      right.region.lower[c] = kept;
    } else {
      // A 2D cut across the third component, which Zoltan makes when all the points of the region are
      // on one spot (no component is longer than another): the left side keeps the whole region, the
      // right side is empty.
      right.region.lower[0] = right.region.upper[0] = at.region.upper[0];
    }
    pending.push_back(right);
    pending.push_back(left);
  }
  for (std::size_t p = 0; p < count; ++p) {
    if (reached[p] != 1) throw bad_tree(fmt::format("reaches part {} {} times", p, reached[p]));
    if (rebuilt[p].lower != zoltan[p].lower || rebuilt[p].upper != zoltan[p].upper)
      throw bad_tree(fmt::format("does not give Zoltan's box {} back", p));
  }
  return boxes;
}

// The local part of partition()'s checks: the first problem with this process's input, or "".
std::string partition_input_error(int rank, int dimension, const std::vector<std::array<double, 3>>& points,
                                  const std::vector<double>& weights) {
  if (dimension != 2 && dimension != 3)
    return fmt::format("partition: dimension {} on process {}; expected 2 or 3", dimension, rank);
  if (weights.size() != points.size())
    return fmt::format("partition: {} weights for {} points on process {}; expected one weight per point",
                       weights.size(), points.size(), rank);
  if (points.size() > max_count)
    return fmt::format("partition: {} points on process {}; Zoltan counts them in int, at most {}", points.size(),
                       rank, max_count);
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (int d = 0; d < dimension; ++d) {
      const double x = points[i][static_cast<std::size_t>(d)];
      if (!(std::abs(x) <= max_coordinate))
        return fmt::format(
            "partition: point {} on process {} has coordinate {} = {}; expected a finite number of magnitude at most "
            "{}",
            i, rank, d, x, max_coordinate);
    }
    const double w = weights[i];
    if (!(w >= 0.0 && w <= FLT_MAX))
      return fmt::format(
          "partition: point {} on process {} has weight {}; expected a finite number >= 0 (at most {}, a float)", i,
          rank, w, FLT_MAX);
  }
  return {};
}

}  // namespace

struct MpiCommunicator::State {
  MPI_Comm comm;
  int rank;
  int size;
  MpiReducer reducer;

  explicit State(MPI_Comm c) : comm(c), rank(rank_of(c)), size(size_of(c)), reducer(c, rank, size) {}
  ~State() {
    if (!mpi_finalized()) MPI_Comm_free(&comm);
  }
  State(const State&) = delete;
  State& operator=(const State&) = delete;
};

MpiCommunicator::MpiCommunicator() : state_(std::make_unique<State>(duplicate_world())) {}

MpiCommunicator::~MpiCommunicator() = default;

int MpiCommunicator::rank() const { return state_->rank; }

int MpiCommunicator::size() const { return state_->size; }

const Reducer& MpiCommunicator::reducer() const { return state_->reducer; }

template <class F>
auto MpiCommunicator::collective(F&& body) const {
  const State& s = *state_;
  check_failures(s.comm, s.rank, s.size);
  try {
    return body();
  } catch (const std::bad_alloc&) {
    abort(fmt::format("process {} of {}: out of memory (std::bad_alloc) in an exchange between processes; use a "
                      "coarser domain.dx, or spread the run over more processes and machines",
                      s.rank, s.size),
          1);
  }
}

Failure MpiCommunicator::fail(const std::string& message, int kind) const {
  const State& s = *state_;
  const int mine = 1;
  int any = 0;
  MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, s.comm);  // the others' check_failures
  Failure f;
  f.process = s.rank;
  f.processes = s.size;
  f.kind = kind;
  f.message = message.empty() ? std::string("an error without a message") : message;
  return first_failure(s.comm, s.rank, s.size, &f);
}

std::vector<std::string> MpiCommunicator::exchange(const std::vector<std::string>& send) const {
  return collective([&]() -> std::vector<std::string> {
    const State& s = *state_;
    const auto n = static_cast<std::size_t>(s.size);
    const auto me = static_cast<std::size_t>(s.rank);
    if (send.size() != n)
      throw std::invalid_argument(fmt::format("exchange: {} parts to send on process {}; expected one per process ({})",
                                              send.size(), s.rank, s.size));
    // Our own part does not travel.
    std::vector<std::uint64_t> send_bytes(n), receive_bytes(n);
    for (std::size_t r = 0; r < n; ++r) send_bytes[r] = r == me ? 0 : send[r].size();
    MPI_Alltoall(send_bytes.data(), 1, MPI_UINT64_T, receive_bytes.data(), 1, MPI_UINT64_T, s.comm);
    const std::uint64_t total_send = std::accumulate(send_bytes.begin(), send_bytes.end(), std::uint64_t{0});
    const std::uint64_t total_receive = std::accumulate(receive_bytes.begin(), receive_bytes.end(), std::uint64_t{0});
    std::string error;
    if (total_send > max_count || total_receive > max_count)
      error = fmt::format(
          "exchange: process {} sends {} bytes and receives {}; MPI counts the bytes of one exchange in int, at most {} "
          "each way: send them in smaller pieces",
          s.rank, total_send, total_receive, max_count);
    if (auto e = first_error(s.comm, s.rank, s.size, error)) throw std::length_error(*e);

    std::vector<int> send_counts(n), send_offsets(n), receive_counts(n), receive_offsets(n);
    std::string send_buffer;
    send_buffer.reserve(total_send);
    int offset = 0;
    for (std::size_t r = 0; r < n; ++r) {
      send_counts[r] = static_cast<int>(send_bytes[r]);
      send_offsets[r] = static_cast<int>(send_buffer.size());
      if (r != me) send_buffer += send[r];
      receive_counts[r] = static_cast<int>(receive_bytes[r]);
      receive_offsets[r] = offset;
      offset += receive_counts[r];
    }
    std::string receive_buffer(total_receive, '\0');
    MPI_Alltoallv(send_buffer.data(), send_counts.data(), send_offsets.data(), MPI_BYTE, receive_buffer.data(),
                  receive_counts.data(), receive_offsets.data(), MPI_BYTE, s.comm);

    std::vector<std::string> received(n);
    for (std::size_t r = 0; r < n; ++r)
      received[r] = r == me ? send[r]
                            : receive_buffer.substr(static_cast<std::size_t>(receive_offsets[r]), receive_bytes[r]);
    return received;
  });
}

std::vector<std::string> MpiCommunicator::gather(const std::string& part) const {
  return collective([&]() -> std::vector<std::string> {
    const State& s = *state_;
    const auto n = static_cast<std::size_t>(s.size);
    // Every process learns every size (not only the root), so that all of them see the same total and
    // agree on the error below without another message.
    const std::uint64_t mine = part.size();
    std::vector<std::uint64_t> bytes(n);
    MPI_Allgather(&mine, 1, MPI_UINT64_T, bytes.data(), 1, MPI_UINT64_T, s.comm);
    const std::uint64_t total = std::accumulate(bytes.begin(), bytes.end(), std::uint64_t{0});
    if (total > max_count)
      throw std::length_error(fmt::format(
          "gather: {} bytes for process 0; MPI counts the bytes of one gather in int, at most {}: gather them in "
          "smaller pieces",
          total, max_count));

    std::vector<int> counts(n), offsets(n);
    int offset = 0;
    for (std::size_t r = 0; r < n; ++r) {
      counts[r] = static_cast<int>(bytes[r]);
      offsets[r] = offset;
      offset += counts[r];
    }
    std::string buffer(s.rank == 0 ? total : 0, '\0');
    MPI_Gatherv(part.data(), static_cast<int>(mine), MPI_BYTE, buffer.data(), counts.data(), offsets.data(), MPI_BYTE,
                0, s.comm);
    if (s.rank != 0) return {};
    std::vector<std::string> parts(n);
    for (std::size_t r = 0; r < n; ++r) parts[r] = buffer.substr(static_cast<std::size_t>(offsets[r]), bytes[r]);
    return parts;
  });
}

std::string MpiCommunicator::broadcast(const std::string& from_root) const {
  return collective([&]() -> std::string {
    const State& s = *state_;
    std::uint64_t bytes = s.rank == 0 ? from_root.size() : 0;
    MPI_Bcast(&bytes, 1, MPI_UINT64_T, 0, s.comm);
    if (bytes > max_count)
      throw std::length_error(fmt::format(
          "broadcast: {} bytes; MPI counts the bytes of one broadcast in int, at most {}: send them in smaller pieces",
          bytes, max_count));
    std::string bytes_of_root = s.rank == 0 ? from_root : std::string(bytes, '\0');
    MPI_Bcast(bytes_of_root.data(), static_cast<int>(bytes), MPI_BYTE, 0, s.comm);
    return bytes_of_root;
  });
}

std::vector<DomainBox> MpiCommunicator::partition(int dimension, const std::vector<std::array<double, 3>>& points,
                                                  const std::vector<double>& weights) const {  return collective([&]() -> std::vector<DomainBox> {
    const State& s = *state_;
    const auto n = static_cast<std::size_t>(s.size);

    // Every process checks its own input; all throw the first process's complaint, or all go on.
    std::string error = partition_input_error(s.rank, dimension, points, weights);
    if (error.empty()) {
      int dims[2] = {dimension, -dimension};
      MPI_Allreduce(MPI_IN_PLACE, dims, 2, MPI_INT, MPI_MIN, s.comm);
      if (dims[0] != -dims[1])
        error = fmt::format("partition: dimension {} on some processes and {} on others; expected the same on all",
                            dims[0], -dims[1]);
    } else {
      // Take part in the other processes' check of the dimensions all the same.
      int dims[2] = {INT_MAX, INT_MAX};
      MPI_Allreduce(MPI_IN_PLACE, dims, 2, MPI_INT, MPI_MIN, s.comm);
    }
    if (auto e = first_error(s.comm, s.rank, s.size, error)) throw std::invalid_argument(*e);

    // Zoltan's weights are floats. Their total is only compared with 0 (a sum of numbers >= 0 is 0
    // whatever its order).
    std::vector<float> float_weights(weights.size());
    std::transform(weights.begin(), weights.end(), float_weights.begin(), [](double w) { return static_cast<float>(w); });
    double totals[2] = {std::accumulate(float_weights.begin(), float_weights.end(), 0.0),
                        static_cast<double>(points.size())};
    MPI_Allreduce(MPI_IN_PLACE, totals, 2, MPI_DOUBLE, MPI_SUM, s.comm);
    const bool unit_weights = totals[0] == 0.0;
    const bool no_points = totals[1] == 0.0;

    if (s.size == 1) return {all_of_space()};
    if (no_points) {
      // All the cuts at +infinity: box 0 is everything, the others are empty.
      std::vector<DomainBox> boxes(n, all_of_space());
      for (std::size_t r = 1; r < n; ++r) boxes[r].lower[0] = std::numeric_limits<double>::infinity();
      for (std::size_t r = 0; r + 1 < n; ++r) boxes[r].upper[0] = std::numeric_limits<double>::infinity();
      return boxes;
    }

    initialize_zoltan();
    ZoltanInput input;
    input.points = &points;
    input.dimension = dimension;
    input.rank = static_cast<ZOLTAN_ID_TYPE>(s.rank);
    input.weights = unit_weights ? std::vector<float>(points.size(), 1.0f) : std::move(float_weights);

    std::unique_ptr<Zoltan_Struct, ZoltanDestroy> zz(Zoltan_Create(s.comm));
    if (!zz) throw std::runtime_error("Zoltan: Zoltan_Create failed");
    Zoltan_Struct* z = zz.get();
    // Nothing on standard output (the run's own output is there).
    set_zoltan_param(z, "DEBUG_LEVEL", "0");
    set_zoltan_param(z, "LB_METHOD", "RCB");
    set_zoltan_param(z, "LB_APPROACH", "PARTITION");
    set_zoltan_param(z, "NUM_GLOBAL_PARTS", std::to_string(s.size));
    set_zoltan_param(z, "NUM_GID_ENTRIES", "2");
    set_zoltan_param(z, "NUM_LID_ENTRIES", "1");
    set_zoltan_param(z, "OBJ_WEIGHT_DIM", "1");
    // The boxes are all we want: no lists of objects to move.
    set_zoltan_param(z, "RETURN_LISTS", "NONE");
    // Keep the tree of cuts, which Zoltan_RCB_Box and Zoltan_RCB_Partition_Tree read.
    set_zoltan_param(z, "KEEP_CUTS", "1");
    // Part r is the same region whichever process held which points before (no renumbering of the
    // parts to keep points where they are), and the median search is the deterministic bisection.
    set_zoltan_param(z, "REMAP", "0");
    set_zoltan_param(z, "RANDOM_PIVOTS", "0");
    // Zoltan's own check of its input and output costs more passes and reductions per call; the input
    // is checked above, and the boxes are checked by rebuilding them (tiling_boxes).
    set_zoltan_param(z, "CHECK_GEOM", "0");
    // Points at the same coordinate stay on one side of a cut, and the cut is halfway between the
    // nearest points on its two sides: a lattice is cut between two of its rows, not through one, and
    // the boxes (lower <= x < upper) give every point the part Zoltan balanced it into.
    set_zoltan_param(z, "RCB_RECTILINEAR_BLOCKS", "1");
    set_zoltan_param(z, "AVERAGE_CUTS", "1");
    zoltan_check(Zoltan_Set_Num_Obj_Fn(z, &zoltan_object_count, &input), "Zoltan_Set_Num_Obj_Fn");
    zoltan_check(Zoltan_Set_Obj_List_Fn(z, &zoltan_objects, &input), "Zoltan_Set_Obj_List_Fn");
    zoltan_check(Zoltan_Set_Num_Geom_Fn(z, &zoltan_dimension, &input), "Zoltan_Set_Num_Geom_Fn");
    zoltan_check(Zoltan_Set_Geom_Multi_Fn(z, &zoltan_coordinates, &input), "Zoltan_Set_Geom_Multi_Fn");

    int changes = 0, global_id_size = 0, local_id_size = 0, imports = 0, exports = 0;
    ZOLTAN_ID_PTR import_global = nullptr, import_local = nullptr, export_global = nullptr, export_local = nullptr;
    int *import_procs = nullptr, *import_parts = nullptr, *export_procs = nullptr, *export_parts = nullptr;
    const int status =
        Zoltan_LB_Partition(z, &changes, &global_id_size, &local_id_size, &imports, &import_global, &import_local,
                            &import_procs, &import_parts, &exports, &export_global, &export_local, &export_procs,
                            &export_parts);
    Zoltan_LB_Free_Part(&import_global, &import_local, &import_procs, &import_parts);
    Zoltan_LB_Free_Part(&export_global, &export_local, &export_procs, &export_parts);
    zoltan_check(status, "Zoltan_LB_Partition");

    return tiling_boxes(z, s.size, dimension);
  });
}

void MpiCommunicator::abort(const std::string& message, int status) const {
  // What this process printed before, then the message as one line in a single write, so that the
  // messages of several processes do not mix within a line.
  std::cout.flush();
  std::fflush(nullptr);
  std::string line = "sluice: error: " + message;
  while (!line.empty() && line.back() == '\n') line.pop_back();
  line += '\n';
  for (std::size_t done = 0; done < line.size();) {
    const ssize_t written = ::write(STDERR_FILENO, line.data() + done, line.size() - done);
    if (written <= 0) break;
    done += static_cast<std::size_t>(written);
  }
  MPI_Abort(MPI_COMM_WORLD, status);
  std::_Exit(status);  // MPI_Abort does not return; this is in case it does
}

// ---- The session ----

bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}

MpiSession::MpiSession(int rank, int size, double init_seconds)
    : rank_(rank), size_(size), init_seconds_(init_seconds) {
  if (size_ > 1) world_ = std::make_unique<MpiCommunicator>();
}

MpiSession::~MpiSession() {
  // An exception leaving main on one process: the others may be waiting for it in a collective call,
  // and MPI_Finalize would wait for them forever. Stop them all instead.
  if (std::uncaught_exceptions() > 0 && size_ > 1) {
    static const char line[] = "sluice: error: a process stopped on an exception; stopping all processes\n";
    [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, line, sizeof line - 1);
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  world_.reset();
  MPI_Finalize();
}

std::unique_ptr<MpiSession> start_mpi_if_launched(int& argc, char**& argv) {
  if (!launched_by_mpi()) return nullptr;
  int started = 0;
  MPI_Initialized(&started);
  if (started != 0 || mpi_finalized())
    throw std::logic_error("start_mpi_if_launched: MPI was started before in this process; expected one session");
  const auto begin = std::chrono::steady_clock::now();
  int provided = MPI_THREAD_SINGLE;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  if (provided < MPI_THREAD_FUNNELED) {
    MPI_Finalize();
    throw std::runtime_error(fmt::format(
        "MPI gives thread level {}; expected at least MPI_THREAD_FUNNELED ({}): OpenMP threads run in each process",
        provided, MPI_THREAD_FUNNELED));
  }
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return std::unique_ptr<MpiSession>(new MpiSession(rank, size, seconds));
}

std::unique_ptr<MpiCommunicator> world_of_started_mpi() {
  int started = 0;
  MPI_Initialized(&started);
  if (started == 0 || mpi_finalized()) return nullptr;
  int provided = MPI_THREAD_SINGLE;
  MPI_Query_thread(&provided);
  if (provided < MPI_THREAD_FUNNELED)
    throw std::runtime_error(fmt::format(
        "MPI was started with thread level {}; expected at least MPI_THREAD_FUNNELED ({}): OpenMP threads run in "
        "each process",
        provided, MPI_THREAD_FUNNELED));
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size < 2) return nullptr;
  return std::make_unique<MpiCommunicator>();
}

}  // namespace sluice
