#pragma once
// Pairs the frames of the two cameras: to trigger edges (triggered modes)
// or to each other (free-run), by timestamp within a tolerance of half a
// frame period. Sequence numbers serve drop accounting only. A frame that
// finds no partner is dropped and counted, never paired with the wrong one.
//
// Pure logic, no threads, no clocks: the caller pushes frames and trigger
// edges (in any interleaving; frames of a stream may arrive slightly out of
// order) and pops pairs in time order. Memory is bounded by max_pending.
#include <cstdint>
#include <deque>
#include <optional>

#include "spinewatch/frames/frame_pair.hpp"
#include "spinewatch/frames/view.hpp"
#include "spinewatch/sync/pairing_stats.hpp"
#include "spinewatch/sync/sequence_tracker.hpp"

namespace spinewatch::sync {

struct PairerOptions {
  double fps = 30.0;
  bool triggered = false;  // match frames to push_trigger() edges, else to each other
  // Match tolerance; 0 = half a frame period.
  std::int64_t tolerance_ns = 0;
  // How long past a frame's time a partner (or trigger) may still arrive
  // out of order before the frame is declared unmatched; <0 = one period.
  std::int64_t reorder_window_ns = -1;
  // Triggered mode: constant delay from the trigger edge to the frame's
  // timestamp, per stream (the V4L2 timestamp is taken at start or end of
  // frame depending on the driver; measure it once per installation).
  std::int64_t frame_latency_ns[2] = {0, 0};
  // Frames per stream (and edges) held while waiting; beyond it the oldest goes.
  std::size_t max_pending = 16;
};

class FramePairer {
 public:
  explicit FramePairer(PairerOptions options);

  void push(View view, Frame frame);
  void push_trigger(std::int64_t t_ns);
  // The next pair, in time order; consecutive sequence numbers from 0.
  std::optional<FramePair> pop();
  // End of stream: pairs what still can be paired, counts the rest.
  void flush();

  const PairingStats& stats() const { return stats_; }
  const PairerOptions& options() const { return options_; }
  std::int64_t tolerance_ns() const { return tolerance_ns_; }

 private:
  struct Pending {
    std::int64_t t_ns;  // frame time minus latency
    Frame frame;
  };
  struct Slot {  // a trigger edge and what has been matched to it
    std::int64_t t_ns;
    std::optional<Frame> frames[2];
  };

  void insert_sorted(std::deque<Pending>& queue, Pending pending);
  void match_free_run(bool final);
  void match_triggered(bool final);
  bool attach_to_slot(int s, Pending& pending);
  void emit(std::int64_t t_ns, Frame frontal, Frame lateral);
  void drop_slot_front(bool overflow);

  PairerOptions options_;
  std::int64_t period_ns_;
  std::int64_t tolerance_ns_;
  std::int64_t reorder_ns_;
  std::deque<Pending> pending_[2];
  std::deque<Slot> slots_;
  std::deque<FramePair> ready_;
  SequenceTracker sequences_[2];
  // Decided horizon: a frame at or before it arrives too late to be paired.
  std::optional<std::int64_t> decided_until_[2];
  std::optional<std::int64_t> decided_trigger_;  // the last edge paired or given up
  std::int64_t newest_[2];
  std::optional<std::int64_t> newest_trigger_;
  std::uint64_t next_sequence_ = 0;
  PairingStats stats_;
};

}  // namespace spinewatch::sync
