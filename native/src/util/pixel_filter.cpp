#include "util/pixel_filter.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace subsplat {

namespace {
constexpr double kA[4] = {0.35875, -0.48829, 0.14128, -0.01168};
}

double blackmanHarris(double x, double filterWidth) {
  double t = x / (2.0 * filterWidth) + 0.5;  // [0, 1] over the support
  if (t < 0.0 || t > 1.0) return 0.0;
  double a = 2.0 * M_PI * t;
  return kA[0] + kA[1] * std::cos(a) + kA[2] * std::cos(2.0 * a) + kA[3] * std::cos(3.0 * a);
}

double blackmanHarrisCdf(double x, double filterWidth) {
  double t = std::clamp(x / (2.0 * filterWidth) + 0.5, 0.0, 1.0);
  double a = 2.0 * M_PI * t;
  double integral = kA[0] * t + (kA[1] * std::sin(a) + kA[2] * std::sin(2.0 * a) / 2.0 + kA[3] * std::sin(3.0 * a) / 3.0) /
                                    (2.0 * M_PI);
  return integral / kA[0];  // the integral over [0, 1] is kA[0]
}

glm::vec2 pixelFilterOffset(int index, float filterWidth) {
  if (index == 0) return glm::vec2(0.0f);  // the pixel's centre
  // Antithetic pairs: samples 2j - 1 and 2j are the pair j's point and its mirror through the
  // centre, so any odd count of samples has its mean at the centre and an even count nearly: the
  // image does not shift with the count (a gradient would brighten or darken).
  int pair = (index + 1) / 2;
  float sign = index % 2 == 1 ? 1.0f : -1.0f;
  // R2: the plastic number's powers (Roberts 2018).
  const double g1 = 0.7548776662466927, g2 = 0.5698402909980532;
  double u[2] = {std::fmod(0.5 + g1 * pair, 1.0), std::fmod(0.5 + g2 * pair, 1.0)};
  glm::vec2 offset;
  for (int axis = 0; axis < 2; ++axis) {  // the CDF's inverse by bisection (monotone, smooth)
    double lo = -filterWidth, hi = filterWidth;
    for (int i = 0; i < 40; ++i) {
      double mid = 0.5 * (lo + hi);
      (blackmanHarrisCdf(mid, filterWidth) < u[axis] ? lo : hi) = mid;
    }
    offset[axis] = float(0.5 * (lo + hi));
  }
  return sign * offset;
}

SsCameraDesc jitteredCamera(const SsCameraDesc& camera, glm::vec2 offset, int width, int height) {
  // Clip space moved by -offset: what was `offset` pixels away lands on the pixel's centre.
  glm::mat4 shift = glm::translate(glm::mat4(1.0f), glm::vec3(-2.0f * offset.x / float(width),
                                                             -2.0f * offset.y / float(height), 0.0f));
  glm::mat4 clip = shift * glm::make_mat4(camera.view_to_clip);
  SsCameraDesc out = camera;
  std::copy(glm::value_ptr(clip), glm::value_ptr(clip) + 16, out.view_to_clip);
  return out;
}

}  // namespace subsplat
