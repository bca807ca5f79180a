// GL timer and fragment-invocation queries per pipeline stage. A span may name
// a part of the splatting stage (a splatting level, the accumulation, or the selection), which
// SsStats reports besides the stage total. Results are read once, in collect(),
// so the queries never stall the frame. One profiler lives per context: its
// query objects are made once and reused by the spans of every later frame.
#pragma once

#include <chrono>
#include <vector>

#include "gl/gl.h"
#include "subsplat/subsplat.h"

namespace subsplat {

class StageProfiler {
 public:
  static constexpr int kWhole = -1;         // the stage only
  static constexpr int kAccumulation = 8;   // splatting: eq. 17; 0..7: splatting level k
  static constexpr int kSelection = 9;      // splatting: Algorithm 1's sample list (select_samples.comp)
  StageProfiler();
  void newFrame();  // forgets the spans of a frame that ended without collect() (an error)
  void begin(SsStage stage, int part = kWhole);  // one span at a time
  void end();
  bool countsFragments() const { return statistics_; }
  // Waits for the results and adds them to stats. Timer results longer than the frame's wall time
  // since newFrame() are not times (llvmpipe's first query in a context has reported the time since
  // boot): the frame's times are then left out and timers_available is 0.
  // Fragment counts above kMaxFragmentsPerSecond over the frame's wall time are not counts either
  // (NVIDIA's driver 580 returned 2^64 - 2.7e10 for a 13-second splatting draw on an H200,
  // docs/BENCHMARKS.md, "On a GPU"): the frame's counts are then left out and
  // statistics_available is 0.
  void collect(SsStats& stats);
  static constexpr double kMaxFragmentsPerSecond = 1e12;  // about ten times today's largest GPUs

 private:
  struct Span {
    SsStage stage;
    int part;
  };
  std::vector<Span> spans_;  // span i uses times_[i] and fragments_[i]
  std::vector<gl::Query> times_, fragments_;  // the pool, as many as the longest frame had spans
  bool timers_ = false, statistics_ = false, open_ = false;
  std::chrono::steady_clock::time_point frameStart_;
};

}  // namespace subsplat
