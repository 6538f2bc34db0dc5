// The choice of thread count by measurement (io/thread_governor.hpp), on a model machine whose step
// times are given: the run keeps its threads where they are faster, comes down to fewer where the
// machine is busy, goes back up when it is quiet again, and every process decides alike.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <vector>

#include "sluice/io/thread_governor.hpp"

using sluice::ThreadGovernor;

namespace {

double same(double v) { return v; }

// Steps the governor `steps` times with step times from seconds(threads, step); returns the thread
// count of each step.
std::vector<int> drive(ThreadGovernor& g, long steps, const std::function<double(int, long)>& seconds, long first = 0) {
  std::vector<int> used;
  for (long s = first; s < first + steps; ++s) {
    used.push_back(g.threads());
    g.stepped(seconds(g.threads(), s));
  }
  return used;
}

double share_at(const std::vector<int>& used, int threads) {
  return static_cast<double>(std::count(used.begin(), used.end(), threads)) / static_cast<double>(used.size());
}

}  // namespace

TEST(ThreadGovernor, OneThreadNeverAsksTheOtherProcesses) {
  int calls = 0;
  ThreadGovernor g(1, true, [&](double v) { ++calls; return v; });
  const auto used = drive(g, 10000, [](int, long) { return 1e-3; });
  EXPECT_EQ(share_at(used, 1), 1.0);
  EXPECT_EQ(calls, 0);
  ASSERT_EQ(g.shares().size(), 1u);
  EXPECT_EQ(g.shares()[0].steps, 10000);
}

TEST(ThreadGovernor, FixedKeepsItsCountWhereFewerWouldBeFaster) {
  int calls = 0;
  ThreadGovernor g(2, false, [&](double v) { ++calls; return v; });
  const auto used = drive(g, 10000, [](int threads, long) { return threads == 2 ? 2e-3 : 1e-3; });
  EXPECT_EQ(share_at(used, 2), 1.0);
  EXPECT_EQ(calls, 0);
}

TEST(ThreadGovernor, AQuietMachineKeepsEveryThread) {
  // Two threads 1.8 times as fast as one: the probes at one thread are a small share of the steps.
  ThreadGovernor g(2, true, same);
  const auto used = drive(g, 200000, [](int threads, long) { return threads == 2 ? 1e-3 / 1.8 : 1e-3; });
  EXPECT_EQ(used.front(), 2);
  EXPECT_EQ(g.threads(), 2);
  EXPECT_GT(share_at(used, 2), 0.99);
}

TEST(ThreadGovernor, ABusyMachineComesDownToFewerAndGoesBackUpWhenQuiet) {
  // Busy for the first 20,000 steps (two threads take 1.3 times as long as one), quiet afterwards;
  // below its most threads the run probes up at least every 10 s (here 18,000 quiet steps).
  ThreadGovernor g(2, true, same);
  const auto seconds = [](int threads, long step) {
    const bool busy = step < 20000;
    if (threads == 1) return 1e-3;
    return busy ? 1.3e-3 : 1e-3 / 1.8;
  };
  const auto busy = drive(g, 20000, seconds);
  EXPECT_GT(share_at(busy, 1), 0.95);
  const auto quiet = drive(g, 200000, seconds, 20000);
  EXPECT_EQ(g.threads(), 2);
  EXPECT_GT(share_at(quiet, 2), 0.9);
  EXPECT_GT(share_at(std::vector<int>(quiet.begin() + 20000, quiet.end()), 2), 0.99);
}

TEST(ThreadGovernor, ManyThreadsComeDownByHalves) {
  // Eight threads on a machine where four are fastest: 8 -> 4, and it stays there.
  ThreadGovernor g(8, true, same);
  const auto used = drive(g, 100000, [](int threads, long) {
    switch (threads) {
      case 8: return 0.5e-3;
      case 4: return 0.3e-3;
      case 2: return 0.5e-3;
      default: return 1e-3;
    }
  });
  EXPECT_EQ(g.threads(), 4);
  EXPECT_GT(share_at(used, 4), 0.9);
}

TEST(ThreadGovernor, ProcessesWithDifferentTimesDecideAlike) {
  // Two processes whose own step times differ (one twice the other's) but whose windows' times are
  // combined: they ask at the same steps and keep the same counts.
  std::vector<double> asked_a, asked_b;
  const auto machine = [](double scale) {
    return [scale](int threads, long step) { return scale * (threads == 2 && step > 5000 ? 1.5e-3 : 1e-3); };
  };
  ThreadGovernor a(2, true, [&](double v) { asked_a.push_back(v); return 2.0 * v; });
  ThreadGovernor b(2, true, [&](double v) { asked_b.push_back(v); return v; });
  const auto used_a = drive(a, 30000, machine(1.0));
  const auto used_b = drive(b, 30000, machine(2.0));
  EXPECT_EQ(used_a, used_b);
  EXPECT_EQ(asked_a.size(), asked_b.size());
  EXPECT_EQ(a.threads(), 1);
}
