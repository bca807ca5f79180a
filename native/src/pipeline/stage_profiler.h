// GL timer and fragment-invocation queries per pipeline stage.
#pragma once

#include <vector>

#include "gl/gl.h"
#include "subsplat/subsplat.h"

namespace subsplat {

class StageProfiler {
 public:
  StageProfiler();
  void begin(SsStage stage);  // one stage at a time
  void end();
  void collect(SsStats& stats);  // waits for the results, adds them to stats

 private:
  struct Span {
    SsStage stage;
    gl::Query time, fragments;
  };
  std::vector<Span> spans_;
  bool timers_ = false, statistics_ = false, open_ = false;
};

}  // namespace subsplat
