// The GL layer: what its errors say.
#include "gl/gl.h"

#include <gtest/gtest.h>

#include <string>

#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "util/error.h"

namespace subsplat {
namespace {

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
