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
// by every later one: frames of the same scene make no GL query objects.
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
  ASSERT_TRUE(stats.timers_available) << "no timer queries: nothing to count";
  const int64_t madeByFirstFrame = gl::Query::made(), liveAfterFirstFrame = gl::Query::live();
  EXPECT_GT(madeByFirstFrame, madeBefore);
  for (int frame = 2; frame <= 5; ++frame) {
    ASSERT_EQ(ssRender(context, 16, 16, rgba.data()), SS_OK) << ssGetLastError();
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
