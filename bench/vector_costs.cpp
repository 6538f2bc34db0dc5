// What the vector operations a compacted neighbour list would need cost on this CPU, beside the
// fused multiply-add the pair arithmetic is made of (sluice-bench-micro --benchmark_filter=VectorCost).
// A list of neighbours compacted from the candidate vectors (instead of the contiguous vectors the
// pair loop evaluates, half of whose lanes or more are empty) takes each neighbour's fields either by
// a gather (GatherIndex) or by packing the lanes that hold a neighbour into a staging array
// (Compress, then a store at the array's end, then a whole-vector load once it holds a vector's
// worth; CompressStore below, with one permutation per mask for all the fields), and gives the
// neighbours their share back by a scatter (ScatterIndex) or the reverse. Each
// benchmark runs four independent operations per pass over data in the first-level cache; the
// items/s it reports are vector operations per second, on the instruction set Highway picks for
// this CPU (the label).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "bench/vector_costs.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h

#include <hwy/highway.h>

#include <cstdint>
#include <cstring>

HWY_BEFORE_NAMESPACE();
namespace vector_costs::HWY_NAMESPACE {

namespace hn = hwy::HWY_NAMESPACE;
using D = hn::ScalableTag<double>;
using DI = hn::RebindToSigned<D>;

constexpr std::size_t kTable = 4096;  // doubles: 32 KiB, in the first-level cache
HWY_ALIGN double table[kTable];

// Lane k of index vector v: a spread of places in the table, different for each v.
HWY_INLINE hn::Vec<DI> spread(int v) {
  const DI di;
  HWY_ALIGN std::int64_t index[hn::MaxLanes(DI())];
  for (std::size_t k = 0; k < hn::Lanes(di); ++k)
    index[k] = static_cast<std::int64_t>((977 * (k + 1) + 131 * static_cast<std::size_t>(v)) % kTable);
  return hn::Load(di, index);
}

const char* target() { return hwy::TargetName(HWY_TARGET); }

double gathers(long passes) {
  const D d;
  for (std::size_t k = 0; k < kTable; ++k) table[k] = 0.5 * static_cast<double>(k);
  const auto i0 = spread(0), i1 = spread(1), i2 = spread(2), i3 = spread(3);
  auto a0 = hn::Zero(d), a1 = a0, a2 = a0, a3 = a0;
  for (long p = 0; p < passes; ++p) {
    a0 = hn::Add(a0, hn::GatherIndex(d, table, i0));
    a1 = hn::Add(a1, hn::GatherIndex(d, table, i1));
    a2 = hn::Add(a2, hn::GatherIndex(d, table, i2));
    a3 = hn::Add(a3, hn::GatherIndex(d, table, i3));
  }
  return hn::GetLane(hn::SumOfLanes(d, hn::Add(hn::Add(a0, a1), hn::Add(a2, a3))));
}

double scatters(long passes) {
  const D d;
  const auto i0 = spread(0), i1 = spread(1), i2 = spread(2), i3 = spread(3);
  auto v = hn::Set(d, 1.0);
  for (long p = 0; p < passes; ++p) {
    hn::ScatterIndex(v, d, table, i0);
    hn::ScatterIndex(v, d, table + 8, i1);
    hn::ScatterIndex(v, d, table + 16, i2);
    hn::ScatterIndex(v, d, table + 24, i3);
    v = hn::Add(v, hn::Set(d, 1.0));
  }
  return table[kTable / 2];
}

// The permutation that packs the lanes of an 8-bit mask first (in order), then the others: what a
// compacted loop computes once per candidate vector and applies to each of its fields.
struct PackTable {
  HWY_ALIGN std::int64_t index[256][8];
  PackTable() {
    for (int m = 0; m < 256; ++m) {
      int k = 0;
      for (int lane = 0; lane < 8; ++lane)
        if (m >> lane & 1) index[m][k++] = lane;
      for (int lane = 0; lane < 8; ++lane)
        if (!(m >> lane & 1)) index[m][k++] = lane;
    }
  }
};

// Four fields of the lanes of a mask that varies from pass to pass (a linear congruential sequence)
// packed onto the ends of four staging arrays by one permutation; each time they hold a whole
// vector, it is loaded (as the evaluation would) and the rest moved to the front. (Not Highway's
// Compress: in Highway 1.0.3 compiled by GCC 12 it copies its 2 KiB table onto the stack at every
// call, 21 ns a call measured on an AMD EPYC.)
double compress_stores(long passes) {
  static const PackTable pack;
  const D d;
  const DI di;
  const std::size_t N = hn::Lanes(d);
  const unsigned lanes_mask = N >= 8 ? 0xFFu : (1u << N) - 1u;
  HWY_ALIGN double stage[4][4 * hn::MaxLanes(D())];
  std::memset(stage, 0, sizeof stage);
  const auto f0 = hn::Iota(d, 1.0), f1 = hn::Iota(d, 2.0), f2 = hn::Iota(d, 3.0), f3 = hn::Iota(d, 4.0);
  auto sum = hn::Zero(d);
  std::size_t count = 0;
  std::uint32_t seed = 1;
  for (long p = 0; p < passes; ++p) {
    seed = seed * 1103515245u + 12345u;
    const unsigned m = (seed >> 16) & lanes_mask;
    const auto order = hn::IndicesFromVec(d, hn::Load(di, pack.index[m]));
    hn::StoreU(hn::TableLookupLanes(f0, order), d, stage[0] + count);
    hn::StoreU(hn::TableLookupLanes(f1, order), d, stage[1] + count);
    hn::StoreU(hn::TableLookupLanes(f2, order), d, stage[2] + count);
    hn::StoreU(hn::TableLookupLanes(f3, order), d, stage[3] + count);
    count += static_cast<std::size_t>(__builtin_popcount(m));
    if (count >= N) {
      for (auto& s : stage) {
        sum = hn::Add(sum, hn::Load(d, s));
        hn::Store(hn::LoadU(d, s + N), d, s);
      }
      count -= N;
    }
  }
  return hn::GetLane(hn::SumOfLanes(d, sum));
}

// Eight independent chains (the pair arithmetic's operation; the latency of each chain is hidden).
double mul_adds(long passes) {
  const D d;
  const auto m = hn::Set(d, 1.0000001), c = hn::Set(d, 1e-9);
  auto a0 = hn::Iota(d, 0.0), a1 = hn::Iota(d, 1.0), a2 = hn::Iota(d, 2.0), a3 = hn::Iota(d, 3.0);
  auto a4 = hn::Iota(d, 4.0), a5 = hn::Iota(d, 5.0), a6 = hn::Iota(d, 6.0), a7 = hn::Iota(d, 7.0);
  for (long p = 0; p < passes; ++p) {
    a0 = hn::MulAdd(a0, m, c);
    a1 = hn::MulAdd(a1, m, c);
    a2 = hn::MulAdd(a2, m, c);
    a3 = hn::MulAdd(a3, m, c);
    a4 = hn::MulAdd(a4, m, c);
    a5 = hn::MulAdd(a5, m, c);
    a6 = hn::MulAdd(a6, m, c);
    a7 = hn::MulAdd(a7, m, c);
  }
  const auto s = hn::Add(hn::Add(hn::Add(a0, a1), hn::Add(a2, a3)), hn::Add(hn::Add(a4, a5), hn::Add(a6, a7)));
  return hn::GetLane(hn::SumOfLanes(d, s));
}

}  // namespace vector_costs::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE

#include <benchmark/benchmark.h>

namespace vector_costs {

HWY_EXPORT(target);
HWY_EXPORT(gathers);
HWY_EXPORT(scatters);
HWY_EXPORT(compress_stores);
HWY_EXPORT(mul_adds);

namespace {

constexpr long kPasses = 1 << 16;

template <class F>
void run(benchmark::State& state, F f, long operations_per_pass) {
  for (auto _ : state) benchmark::DoNotOptimize(f(kPasses));
  state.SetItemsProcessed(state.iterations() * kPasses * operations_per_pass);
  state.SetLabel(HWY_DYNAMIC_DISPATCH(target)());
}

void VectorCostGather(benchmark::State& s) { run(s, HWY_DYNAMIC_DISPATCH(gathers), 4); }
void VectorCostScatter(benchmark::State& s) { run(s, HWY_DYNAMIC_DISPATCH(scatters), 4); }
void VectorCostCompressStore(benchmark::State& s) { run(s, HWY_DYNAMIC_DISPATCH(compress_stores), 4); }
void VectorCostMulAdd(benchmark::State& s) { run(s, HWY_DYNAMIC_DISPATCH(mul_adds), 8); }

}  // namespace

BENCHMARK(VectorCostGather);
BENCHMARK(VectorCostScatter);
BENCHMARK(VectorCostCompressStore);
BENCHMARK(VectorCostMulAdd);

}  // namespace vector_costs

#endif  // HWY_ONCE
