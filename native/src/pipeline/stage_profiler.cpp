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

void StageProfiler::begin(SsStage stage, int part) {
  end();
  Span span{stage, part, {}, {}};
  if (timers_) {
    span.time = newQuery();
    glBeginQuery(GL_TIME_ELAPSED, span.time.id());
  }
  if (statistics_) {
    span.fragments = newQuery();
    glBeginQuery(GL_FRAGMENT_SHADER_INVOCATIONS_ARB, span.fragments.id());
  }
  spans_.push_back(std::move(span));
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
  for (Span& span : spans_) {
    GLuint64 nanoseconds = 0, fragments = 0;
    if (span.time) glGetQueryObjectui64v(span.time.id(), GL_QUERY_RESULT, &nanoseconds);
    if (span.fragments) glGetQueryObjectui64v(span.fragments.id(), GL_QUERY_RESULT, &fragments);
    double ms = double(nanoseconds) * 1e-6;
    stats.stage_ms[span.stage] += ms;
    stats.fragment_invocations[span.stage] += fragments;
    if (span.part >= 0 && span.part < kAccumulation) {
      stats.splat_level_ms[span.part] += ms;
      stats.splat_level_fragments[span.part] += fragments;
    } else if (span.part == kAccumulation) {
      stats.accumulation_ms += ms;
      stats.accumulation_fragments += fragments;
    }
  }
  stats.timers_available = timers_;
  stats.statistics_available = statistics_;
  spans_.clear();
}

}  // namespace subsplat
