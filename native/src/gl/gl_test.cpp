// The GL layer: what its objects cost per frame and what its errors say.
#include "gl/gl.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/scenes.h"
#include "util/error.h"

namespace subsplat {
namespace {

// The profiler's timer and pipeline-statistics queries are made in the first frame and reused
// by every later one: frames of the same scene make no GL query objects. Their times fit in the
// frame's wall time.
TEST(GlQueries, ProfilerQueriesAreMadeOnceAndReusedByLaterFrames) {
  testing::EglContext gl;
  SsContext context = nullptr;
  ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError();
  testing::Sphere sphere{24, 12};
  ASSERT_EQ(testing::setLitSphere(context, sphere, testing::skinMaterial(100.0f)), SS_OK) << ssGetLastError();
  SsSettings settings{};
  ASSERT_EQ(ssGetSettings(context, &settings), SS_OK);
  settings.method = SS_METHOD_FULL;
  settings.irradiance_resolution = 64;
  ASSERT_EQ(ssSetSettings(context, &settings), SS_OK);
  std::vector<float> rgba(16 * 16 * 4);
  const int64_t madeBefore = gl::Query::made();
  ASSERT_EQ(ssRender(context, 16, 16, rgba.data()), SS_OK) << ssGetLastError();
  SsStats stats{};
  ASSERT_EQ(ssGetStats(context, &stats), SS_OK);
  // The first frame of a process's first context may report timers_available 0: llvmpipe's
  // first timer query has returned the time since boot (StageProfiler::collect leaves it out).
  const int64_t madeByFirstFrame = gl::Query::made(), liveAfterFirstFrame = gl::Query::live();
  EXPECT_GT(madeByFirstFrame, madeBefore);
  for (int frame = 2; frame <= 5; ++frame) {
    ASSERT_EQ(ssRender(context, 16, 16, rgba.data()), SS_OK) << ssGetLastError();
    ASSERT_EQ(ssGetStats(context, &stats), SS_OK);
    double stages = 0.0;
    for (double ms : stats.stage_ms) stages += ms;
    EXPECT_TRUE(stats.timers_available) << "frame " << frame;
    EXPECT_LE(stages, 1.5 * stats.frame_ms + 1.0) << "GPU stage times within the frame's wall time, frame " << frame;
    EXPECT_EQ(gl::Query::made(), madeByFirstFrame) << "queries made in frame " << frame;
    EXPECT_EQ(gl::Query::live(), liveAfterFirstFrame) << "queries live after frame " << frame;
  }
  ASSERT_EQ(ssReleaseContext(context), SS_OK);
}

// An incomplete framebuffer's status is named in hexadecimal, as the GL headers write it.
TEST(GlErrors, IncompleteFramebufferStatusIsHexadecimal) {
  testing::EglContext gl;
  try {
    gl::Framebuffer framebuffer = gl::makeFramebuffer({}, 0);  // no attachment at all
    FAIL() << "a framebuffer without attachments was complete";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), SS_GL_ERROR);
    EXPECT_NE(std::string(e.what()).find("status 0x8cd7"), std::string::npos)  // ..._MISSING_ATTACHMENT
        << e.what();
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace
}  // namespace subsplat
