#include "pipeline/stage_profiler.h"

#include <epoxy/gl.h>

namespace subsplat {

StageProfiler::StageProfiler() {
  timers_ = epoxy_gl_version() >= 33 || epoxy_has_gl_extension("GL_ARB_timer_query");
  statistics_ = epoxy_gl_version() >= 46 || epoxy_has_gl_extension("GL_ARB_pipeline_statistics_query");
}

static gl::Query newQuery() {
  GLuint id = 0;
  glGenQueries(1, &id);
  return gl::Query(id);
}

void StageProfiler::newFrame() {
  end();
  spans_.clear();
  frameStart_ = std::chrono::steady_clock::now();
}

void StageProfiler::begin(SsStage stage, int part) {
  end();
  size_t i = spans_.size();
  if (timers_) {
    if (i == times_.size()) times_.push_back(newQuery());
    glBeginQuery(GL_TIME_ELAPSED, times_[i].id());
  }
  if (statistics_) {
    if (i == fragments_.size()) fragments_.push_back(newQuery());
    glBeginQuery(GL_FRAGMENT_SHADER_INVOCATIONS_ARB, fragments_[i].id());
  }
  spans_.push_back({stage, part});
  open_ = true;
}

void StageProfiler::end() {
  if (!open_) return;
  if (timers_) glEndQuery(GL_TIME_ELAPSED);
  if (statistics_) glEndQuery(GL_FRAGMENT_SHADER_INVOCATIONS_ARB);
  open_ = false;
}

void StageProfiler::collect(SsStats& stats) {
  end();
  std::vector<GLuint64> nanoseconds(spans_.size(), 0);
  if (timers_)
    for (size_t i = 0; i < spans_.size(); ++i) glGetQueryObjectui64v(times_[i].id(), GL_QUERY_RESULT, &nanoseconds[i]);
  double wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frameStart_).count();
  bool timesValid = timers_;
  for (GLuint64 ns : nanoseconds)
    if (double(ns) * 1e-6 > 1.5 * wallMs + 1.0) timesValid = false;
  std::vector<GLuint64> counts(spans_.size(), 0);
  if (statistics_)
    for (size_t i = 0; i < spans_.size(); ++i) glGetQueryObjectui64v(fragments_[i].id(), GL_QUERY_RESULT, &counts[i]);
  bool countsValid = statistics_;
  for (GLuint64 n : counts)
    if (double(n) > kMaxFragmentsPerSecond * wallMs * 1e-3 + 1e9) countsValid = false;
  for (size_t i = 0; i < spans_.size(); ++i) {
    const Span& span = spans_[i];
    GLuint64 fragments = countsValid ? counts[i] : 0;
    double ms = timesValid ? double(nanoseconds[i]) * 1e-6 : 0.0;
    stats.stage_ms[span.stage] += ms;
    stats.fragment_invocations[span.stage] += fragments;
    if (span.part >= 0 && span.part < kAccumulation) {
      stats.splat_level_ms[span.part] += ms;
      stats.splat_level_fragments[span.part] += fragments;
    } else if (span.part == kAccumulation) {
      stats.accumulation_ms += ms;
      stats.accumulation_fragments += fragments;
    } else if (span.part == kSelection) {
      stats.selection_ms += ms;
    }
  }
  stats.timers_available = timesValid;
  stats.statistics_available = countsValid;
  spans_.clear();
}

}  // namespace subsplat
