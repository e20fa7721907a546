#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "spinewatch/sync/frame_pairer.hpp"

namespace spinewatch::sync {
namespace {

constexpr std::int64_t kPeriod = 33'333'333;  // 30 fps

Frame frame_at(std::uint64_t seq, std::int64_t t_ns) { return Frame(FrameFormat{}, FrameInfo{seq, t_ns}, nullptr, {}); }

std::vector<FramePair> drain(FramePairer& pairer) {
  std::vector<FramePair> out;
  while (auto p = pairer.pop()) out.push_back(std::move(*p));
  return out;
}

// Every frame pushed is either in a pair or counted as discarded.
void expect_conservation(const FramePairer& pairer) {
  const auto& st = pairer.stats();
  for (int s = 0; s < 2; ++s) {
    EXPECT_EQ(st.frames_in[s], st.pairs + st.drops[s].total_discarded()) << "stream " << s << ": " << st.summary();
  }
}

void expect_well_formed(const std::vector<FramePair>& pairs) {
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    EXPECT_EQ(pairs[i].sequence, i);
    EXPECT_EQ(pairs[i].frontal.sequence(), pairs[i].lateral.sequence()) << "mispair at pair " << i;
    if (i > 0) {
      EXPECT_GT(pairs[i].timestamp_ns, pairs[i - 1].timestamp_ns);
    }
  }
}

TEST(FreeRunPairer, PairsSimultaneousFramesWithMeanTime) {
  FramePairer pairer({.fps = 30.0});
  for (std::uint64_t k = 0; k < 10; ++k) {
    const std::int64_t t = static_cast<std::int64_t>(k) * kPeriod;
    pairer.push(View::Frontal, frame_at(k, t + 1'000'000));
    pairer.push(View::Lateral, frame_at(k, t + 3'000'000));
  }
  auto pairs = drain(pairer);
  ASSERT_EQ(pairs.size(), 10u);
  expect_well_formed(pairs);
  EXPECT_EQ(pairs[4].timestamp_ns, 4 * kPeriod + 2'000'000);
  EXPECT_EQ(pairer.stats().pair_skew.max_abs_ns, 2'000'000);
  pairer.flush();
  expect_conservation(pairer);
}

TEST(FreeRunPairer, DropsOnEitherSideAreCountedNotMispaired) {
  FramePairer pairer({.fps = 30.0});
  std::vector<FramePair> pairs;
  for (std::uint64_t k = 0; k < 20; ++k) {
    const std::int64_t t = static_cast<std::int64_t>(k) * kPeriod;
    if (k != 3 && k != 4) pairer.push(View::Frontal, frame_at(k, t));
    if (k != 9) pairer.push(View::Lateral, frame_at(k, t + 500'000));
    for (auto& p : drain(pairer)) pairs.push_back(std::move(p));
  }
  pairer.flush();
  for (auto& p : drain(pairer)) pairs.push_back(std::move(p));
  EXPECT_EQ(pairs.size(), 17u);
  expect_well_formed(pairs);
  const auto& st = pairer.stats();
  EXPECT_EQ(st.drops[0].unmatched, 1u);  // frontal 9 lost its partner
  EXPECT_EQ(st.drops[1].unmatched, 2u);  // lateral 3 and 4
  EXPECT_EQ(st.drops[0].sequence_gaps, 2u);
  EXPECT_EQ(st.drops[1].sequence_gaps, 1u);
  expect_conservation(pairer);
}

TEST(FreeRunPairer, DuplicatesAreDroppedOnce) {
  FramePairer pairer({.fps = 30.0});
  for (std::uint64_t k = 0; k < 5; ++k) {
    const std::int64_t t = static_cast<std::int64_t>(k) * kPeriod;
    pairer.push(View::Frontal, frame_at(k, t));
    if (k == 2) pairer.push(View::Frontal, frame_at(k, t));
    pairer.push(View::Lateral, frame_at(k, t));
  }
  pairer.flush();
  auto pairs = drain(pairer);
  EXPECT_EQ(pairs.size(), 5u);
  expect_well_formed(pairs);
  EXPECT_EQ(pairer.stats().drops[0].duplicate, 1u);
  EXPECT_EQ(pairer.stats().drops[0].sequence_gaps, 0u);
  expect_conservation(pairer);
}

TEST(FreeRunPairer, ReorderingWithinAStreamStillPairsEveryFrame) {
  FramePairer pairer({.fps = 30.0});
  // Lateral frames 4 and 5 arrive swapped, frontal runs one frame ahead.
  std::vector<std::uint64_t> lateral_order = {0, 1, 2, 3, 5, 4, 6, 7, 8, 9};
  for (std::size_t i = 0; i < 10; ++i) {
    pairer.push(View::Frontal, frame_at(i, static_cast<std::int64_t>(i) * kPeriod));
    const auto k = lateral_order[i];
    pairer.push(View::Lateral, frame_at(k, static_cast<std::int64_t>(k) * kPeriod + 100));
  }
  pairer.flush();
  auto pairs = drain(pairer);
  EXPECT_EQ(pairs.size(), 10u);
  expect_well_formed(pairs);
  EXPECT_EQ(pairer.stats().drops[1].sequence_gaps, 0u);
  expect_conservation(pairer);
}

TEST(FreeRunPairer, ClockJitterWithinToleranceStillPairs) {
  FramePairer pairer({.fps = 30.0});
  // ±12 ms of skew each way, alternating: well inside half a period (16.7 ms).
  for (std::uint64_t k = 0; k < 50; ++k) {
    const std::int64_t t = static_cast<std::int64_t>(k) * kPeriod;
    const std::int64_t skew = (k % 2 == 0 ? 1 : -1) * 12'000'000;
    pairer.push(View::Frontal, frame_at(k, t));
    pairer.push(View::Lateral, frame_at(k, t + skew));
  }
  pairer.flush();
  auto pairs = drain(pairer);
  EXPECT_EQ(pairs.size(), 50u);
  expect_well_formed(pairs);
  EXPECT_EQ(pairer.stats().pair_skew.max_abs_ns, 12'000'000);
}

TEST(FreeRunPairer, FramesFurtherApartThanToleranceAreNeverPaired) {
  FramePairer pairer({.fps = 30.0});
  // The lateral camera is 20 ms behind: more than half a period.
  for (std::uint64_t k = 0; k < 10; ++k) {
    const std::int64_t t = static_cast<std::int64_t>(k) * kPeriod;
    pairer.push(View::Frontal, frame_at(k, t));
    pairer.push(View::Lateral, frame_at(k, t + 20'000'000));
  }
  pairer.flush();
  auto pairs = drain(pairer);
  // Frontal k+1 is 13.3 ms after lateral k: those are the nearest frames in time.
  for (const auto& p : pairs) EXPECT_EQ(p.frontal.sequence(), p.lateral.sequence() + 1);
  EXPECT_EQ(pairs.size(), 9u);
  expect_conservation(pairer);
}

// Reference: the largest set of one-to-one pairs within `tolerance`, found
// by augmenting paths over all frontal × lateral candidates (Kuhn), not by
// walking the streams in time order as the pairer does.
std::size_t largest_matching(const std::vector<std::int64_t>& frontal, const std::vector<std::int64_t>& lateral,
                             std::int64_t tolerance) {
  std::vector<int> partner_of_lateral(lateral.size(), -1);
  std::vector<bool> visited;
  auto augment = [&](auto&& self, std::size_t f) -> bool {
    for (std::size_t l = 0; l < lateral.size(); ++l) {
      if (visited[l] || std::llabs(frontal[f] - lateral[l]) > tolerance) continue;
      visited[l] = true;
      if (partner_of_lateral[l] < 0 || self(self, static_cast<std::size_t>(partner_of_lateral[l]))) {
        partner_of_lateral[l] = static_cast<int>(f);
        return true;
      }
    }
    return false;
  };
  std::size_t size = 0;
  for (std::size_t f = 0; f < frontal.size(); ++f) {
    visited.assign(lateral.size(), false);
    if (augment(augment, f)) ++size;
  }
  return size;
}

// Two free-running cameras near half a period apart, with a scheduler that
// jitters and bunches frames (as under an emulated guest): one lateral frame
// is often within reach of two frontal ones. The pairer, fed in time order as
// a replay feeds it, makes as many pairs as any one-to-one choice could.
TEST(FreeRunPairer, CamerasHalfAPeriodApartPairAsManyFramesAsTheTimestampsAllow) {
  std::mt19937_64 rng(20261204);
  std::uniform_int_distribution<std::int64_t> jitter(-6'000'000, 6'000'000);
  std::bernoulli_distribution bunched(0.2);
  int trials_with_a_shared_lateral = 0;  // the case the scenario is for
  for (int trial = 0; trial < 200; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    std::vector<std::int64_t> times[2];
    const std::int64_t offset = kPeriod / 2 + jitter(rng) / 3;
    for (int s = 0; s < 2; ++s) {
      std::int64_t t = s == 0 ? 0 : offset;
      for (int k = 0; k < 12; ++k) {
        t += bunched(rng) ? kPeriod / 3 : kPeriod + jitter(rng);
        times[s].push_back(t);
      }
    }
    FramePairer pairer({.fps = 30.0});
    std::size_t next[2] = {0, 0};
    while (next[0] < times[0].size() || next[1] < times[1].size()) {
      const bool frontal_first =
          next[1] == times[1].size() || (next[0] < times[0].size() && times[0][next[0]] <= times[1][next[1]]);
      const int s = frontal_first ? 0 : 1;
      pairer.push(s == 0 ? View::Frontal : View::Lateral, frame_at(next[s], times[s][next[s]]));
      ++next[s];
    }
    pairer.flush();
    const auto pairs = drain(pairer);
    const std::size_t largest = largest_matching(times[0], times[1], pairer.tolerance_ns());
    EXPECT_EQ(pairs.size(), largest);
    const auto frontal_in_reach = std::count_if(times[0].begin(), times[0].end(), [&](std::int64_t f) {
      return std::any_of(times[1].begin(), times[1].end(),
                         [&](std::int64_t l) { return std::llabs(f - l) <= pairer.tolerance_ns(); });
    });
    if (static_cast<std::size_t>(frontal_in_reach) > largest) ++trials_with_a_shared_lateral;
    for (const auto& p : pairs)
      EXPECT_LE(std::llabs(p.frontal.timestamp_ns() - p.lateral.timestamp_ns()), pairer.tolerance_ns());
    expect_conservation(pairer);
  }
  EXPECT_GT(trials_with_a_shared_lateral, 20);
}

TEST(FreeRunPairer, StalledCameraKeepsMemoryBoundedAndRecovers) {
  PairerOptions options{.fps = 30.0};
  options.max_pending = 8;
  FramePairer pairer(options);
  std::vector<FramePair> pairs;
  for (std::uint64_t k = 0; k < 300; ++k) {
    const std::int64_t t = static_cast<std::int64_t>(k) * kPeriod;
    pairer.push(View::Frontal, frame_at(k, t));
    if (k < 10 || k >= 200) pairer.push(View::Lateral, frame_at(k, t));
    for (auto& p : drain(pairer)) pairs.push_back(std::move(p));
  }
  pairer.flush();
  for (auto& p : drain(pairer)) pairs.push_back(std::move(p));
  expect_well_formed(pairs);
  EXPECT_EQ(pairs.size(), 110u);
  const auto& st = pairer.stats();
  EXPECT_GT(st.drops[0].overflow, 150u);
  EXPECT_EQ(st.drops[1].sequence_gaps, 190u);
  expect_conservation(pairer);
}

TEST(TriggeredPairer, PairsFramesToTheirEdgeWithTheEdgeTime) {
  PairerOptions options{.fps = 30.0, .triggered = true};
  options.frame_latency_ns[0] = 5'000'000;
  options.frame_latency_ns[1] = 6'000'000;
  FramePairer pairer(options);
  for (std::uint64_t k = 0; k < 10; ++k) {
    const std::int64_t t = 1'000'000'000 + static_cast<std::int64_t>(k) * kPeriod;
    // Frames may be pushed before their edge (other thread).
    pairer.push(View::Lateral, frame_at(100 + k, t + 6'000'000));
    pairer.push_trigger(t);
    pairer.push(View::Frontal, frame_at(500 + k, t + 5'200'000));
  }
  auto pairs = drain(pairer);
  ASSERT_EQ(pairs.size(), 10u);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    EXPECT_EQ(pairs[i].sequence, i);
    EXPECT_EQ(pairs[i].timestamp_ns, 1'000'000'000 + static_cast<std::int64_t>(i) * kPeriod);
    EXPECT_EQ(pairs[i].frontal.sequence(), 500 + i);
    EXPECT_EQ(pairs[i].lateral.sequence(), 100 + i);
  }
  EXPECT_EQ(pairer.stats().trigger_skew[0].max_abs_ns, 200'000);
  EXPECT_EQ(pairer.stats().trigger_skew[1].max_abs_ns, 0);
}

TEST(TriggeredPairer, MissingFramesAndEdgesAreCounted) {
  FramePairer pairer({.fps = 30.0, .triggered = true});
  for (std::uint64_t k = 0; k < 30; ++k) {
    const std::int64_t t = static_cast<std::int64_t>(k) * kPeriod;
    if (k != 7) pairer.push_trigger(t);
    if (k != 12) pairer.push(View::Frontal, frame_at(k, t + 1'000'000));
    if (k != 20 && k != 21) pairer.push(View::Lateral, frame_at(k, t + 2'000'000));
  }
  pairer.flush();
  auto pairs = drain(pairer);
  expect_well_formed(pairs);
  EXPECT_EQ(pairs.size(), 26u);
  const auto& st = pairer.stats();
  EXPECT_EQ(st.triggers_unpaired, 3u);      // edges 12, 20, 21
  EXPECT_EQ(st.drops[0].unmatched, 1u + 2u);  // frontal 7 had no edge; 20, 21 no partner
  EXPECT_EQ(st.drops[1].unmatched, 1u + 1u);  // lateral 7 had no edge; 12 no partner
  expect_conservation(pairer);
}

TEST(TriggeredPairer, TriggerThatStopsKeepsMemoryBounded) {
  PairerOptions options{.fps = 30.0, .triggered = true};
  options.max_pending = 6;
  FramePairer pairer(options);
  for (std::uint64_t k = 0; k < 200; ++k) {
    const std::int64_t t = static_cast<std::int64_t>(k) * kPeriod;
    if (k < 10) pairer.push_trigger(t);
    pairer.push(View::Frontal, frame_at(k, t));
    pairer.push(View::Lateral, frame_at(k, t));
  }
  auto pairs = drain(pairer);
  EXPECT_EQ(pairs.size(), 10u);
  expect_well_formed(pairs);
  EXPECT_GE(pairer.stats().drops[0].overflow, 200u - 10u - 6u);
  pairer.flush();
  expect_conservation(pairer);
}

TEST(TriggeredPairer, StalledCameraKeepsEdgesBounded) {
  PairerOptions options{.fps = 30.0, .triggered = true};
  options.max_pending = 6;
  FramePairer pairer(options);
  for (std::uint64_t k = 0; k < 200; ++k) {
    const std::int64_t t = static_cast<std::int64_t>(k) * kPeriod;
    pairer.push_trigger(t);
    pairer.push(View::Frontal, frame_at(k, t));
    if (k < 10) pairer.push(View::Lateral, frame_at(k, t));
  }
  auto pairs = drain(pairer);
  EXPECT_EQ(pairs.size(), 10u);
  EXPECT_GE(pairer.stats().triggers_unpaired, 200u - 10u - 6u);
  pairer.flush();
  expect_conservation(pairer);
}

// Ground truth by construction: exposure k gives both cameras sequence k.
struct RandomRun {
  std::size_t expected_pairs = 0;
  std::vector<FramePair> pairs;
  PairingStats stats;
};

RandomRun run_random(bool triggered, std::uint32_t seed) {
  constexpr std::size_t kExposures = 100'000;
  std::mt19937_64 rng(seed);
  std::bernoulli_distribution drop(0.05);
  std::normal_distribution<double> jitter(0.0, 2e6);
  std::uniform_int_distribution<std::int64_t> delivery_delay(0, 15'000'000);
  struct Event {
    std::int64_t arrival;
    int kind;  // 0 frontal, 1 lateral, 2 trigger
    std::uint64_t seq;
    std::int64_t t;
  };
  std::vector<Event> events;
  RandomRun run;
  const std::int64_t lateral_offset = triggered ? 4'000'000 : 3'000'000;
  for (std::size_t k = 0; k < kExposures; ++k) {
    const std::int64_t t = 5'000'000'000 + static_cast<std::int64_t>(k) * kPeriod;
    const bool has_f = !drop(rng), has_l = !drop(rng);
    const bool has_trigger = !triggered || !std::bernoulli_distribution(0.01)(rng);
    if (has_f && has_l && has_trigger) ++run.expected_pairs;
    if (triggered && has_trigger) events.push_back({t + delivery_delay(rng), 2, k, t});
    const auto tf = t + static_cast<std::int64_t>(jitter(rng));
    const auto tl = t + lateral_offset + static_cast<std::int64_t>(jitter(rng));
    if (has_f) events.push_back({tf + 2'000'000 + delivery_delay(rng), 0, k, tf});
    if (has_l) events.push_back({tl + 2'000'000 + delivery_delay(rng), 1, k, tl});
  }
  std::stable_sort(events.begin(), events.end(), [](const Event& a, const Event& b) { return a.arrival < b.arrival; });

  PairerOptions options{.fps = 30.0, .triggered = triggered};
  options.frame_latency_ns[1] = triggered ? lateral_offset : 0;
  FramePairer pairer(options);
  run.pairs.reserve(kExposures);
  for (const auto& e : events) {
    if (e.kind == 2) {
      pairer.push_trigger(e.t);
    } else {
      pairer.push(e.kind == 0 ? View::Frontal : View::Lateral, frame_at(e.seq, e.t));
    }
    while (auto p = pairer.pop()) run.pairs.push_back(std::move(*p));
  }
  pairer.flush();
  while (auto p = pairer.pop()) run.pairs.push_back(std::move(*p));
  run.stats = pairer.stats();
  return run;
}

// Zero mispairs, consecutive pair numbers, every possible pair found, and
// every loss accounted for by a partner that never existed.
void expect_clean_run(const RandomRun& run) {
  std::size_t mispairs = 0;
  for (std::size_t i = 0; i < run.pairs.size(); ++i) {
    if (run.pairs[i].frontal.sequence() != run.pairs[i].lateral.sequence()) ++mispairs;
    ASSERT_EQ(run.pairs[i].sequence, i);
  }
  EXPECT_EQ(mispairs, 0u);
  EXPECT_EQ(run.pairs.size(), run.expected_pairs) << run.stats.summary();
  for (int s = 0; s < 2; ++s) {
    EXPECT_EQ(run.stats.frames_in[s], run.stats.pairs + run.stats.drops[s].total_discarded());
    // Every loss is a frame whose partner never existed, none is forced by memory or order.
    EXPECT_GT(run.stats.drops[s].unmatched, 1000u);
    EXPECT_EQ(run.stats.drops[s].overflow, 0u);
    EXPECT_EQ(run.stats.drops[s].late, 0u);
    EXPECT_GT(run.stats.drops[s].sequence_gaps, 4000u);
  }
}

TEST(PairerRandomised, FreeRunHundredThousandFramesZeroMispairs) { expect_clean_run(run_random(false, 20240611)); }

TEST(PairerRandomised, TriggeredHundredThousandFramesZeroMispairs) { expect_clean_run(run_random(true, 7)); }

}  // namespace
}  // namespace spinewatch::sync
