// SubEdit files through OpenImageIO (docs/SUBEDIT_FILE.md).
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

#include "material/profile_set.h"
#include "util/error.h"

namespace subsplat {

namespace {

constexpr const char* kFormatKey = "subsplat:format";
constexpr const char* kFormatName = "SubEdit";
constexpr const char* kVersionKey = "subsplat:version";
constexpr int kVersion = 1;
constexpr const char* kSegmentsKey = "subsplat:segments";
constexpr const char* kRadiusKey = "subsplat:radius_mm";

std::string channelName(int knot, int c) { return "P" + std::to_string(knot) + "." + "RGB"[c]; }

// The most light a texel's profile may send out per unit that enters (docs/SUBEDIT_FILE.md): 1,
// with room for the rounding of a fit to float knots.
constexpr double kMaxTotal = 1.001;

[[noreturn]] void fileError(const std::string& path, const std::string& what) {
  fail(SS_INVALID_ARGUMENT, "SubEdit file '" + path + "': " + what);
}

}  // namespace

ProfileSet readSubEditFile(const std::string& path, double tolerance) {
  if (!std::ifstream(path, std::ios::binary)) fileError(path, "does not exist or cannot be opened");
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path);
  if (!in) fileError(path, "is damaged, truncated or not an image (" + OIIO::geterror() + ")");
  if (std::string(in->format_name()) != "openexr")
    fileError(path, "is a " + std::string(in->format_name()) + " image, not OpenEXR");
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.get_string_attribute(kFormatKey) != kFormatName)
    fileError(path, "has no '" + std::string(kFormatKey) + "' = '" + kFormatName + "' metadata: not a SubEdit file");
  int version = spec.get_int_attribute(kVersionKey, -1);
  if (version != kVersion)
    fileError(path, "has format version " + std::to_string(version) + "; this build reads version " +
                        std::to_string(kVersion));
  int segments = spec.get_int_attribute(kSegmentsKey, -1);
  if (segments < 1 || segments > ProfileSet::kMaxSegments)
    fileError(path, "segment count '" + std::string(kSegmentsKey) + "' must be in [1, " +
                        std::to_string(ProfileSet::kMaxSegments) + "], got " + std::to_string(segments));
  float radius = spec.get_float_attribute(kRadiusKey, std::nanf(""));
  if (!(std::isfinite(radius) && radius > 0.0f && radius <= 1e6f))
    fileError(path, "scattering radius '" + std::string(kRadiusKey) + "' must be in (0, 1e6] mm, got " +
                        std::to_string(radius));
  if (spec.width < 1 || spec.height < 1 || spec.width > ProfileSet::kMaxSide || spec.height > ProfileSet::kMaxSide)
    fileError(path, "size " + std::to_string(spec.width) + " x " + std::to_string(spec.height) + " is outside [1, " +
                        std::to_string(ProfileSet::kMaxSide) + "] per side");
  int channels = (segments + 1) * 3;
  if (spec.nchannels != channels)
    fileError(path, "has " + std::to_string(spec.nchannels) + " channels; " + std::to_string(segments) +
                        " segments need " + std::to_string(channels) + " (P0.R ... P" + std::to_string(segments) +
                        ".B)");
  std::map<std::string, int> byName;
  for (int i = 0; i < spec.nchannels; ++i) byName[spec.channel_name(i)] = i;
  std::vector<int> source(static_cast<size_t>(channels));  // file channel of knot k, colour c
  for (int k = 0; k <= segments; ++k)
    for (int c = 0; c < 3; ++c) {
      auto it = byName.find(channelName(k, c));
      if (it == byName.end()) fileError(path, "has no channel " + channelName(k, c));
      source[size_t(3 * k + c)] = it->second;
    }
  size_t texels = size_t(spec.width) * size_t(spec.height);
  if (uint64_t(texels) * uint64_t(channels) > ProfileSet::kMaxSourceFloats)
    fileError(path, "holds more than the 1 GiB budget of profile data");
  std::vector<float> pixels(texels * size_t(channels));
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels.data()))
    fileError(path, "is damaged or truncated (" + in->geterror() + ")");
  in->close();
  // File rows run top down; texel row 0 is v = 0 (the bottom, as in Blender).
  std::vector<float> knots(pixels.size());
  for (int y = 0; y < spec.height; ++y)
    for (int x = 0; x < spec.width; ++x) {
      const float* p = pixels.data() + (size_t(y) * size_t(spec.width) + size_t(x)) * size_t(channels);
      float* k = knots.data() + (size_t(spec.height - 1 - y) * size_t(spec.width) + size_t(x)) * size_t(channels);
      for (int j = 0; j < channels; ++j) k[j] = p[source[size_t(j)]];
    }
  try {
    return ProfileSet::fromTexels(spec.width, spec.height, segments, radius, knots.data(), tolerance, kMaxTotal);
  } catch (const Error& e) {
    fileError(path, e.what());
  }
}

void writeSubEditFile(const ProfileSet& set, const std::string& path) {
  int channels = (set.segments() + 1) * 3, width = set.width(), height = set.height();
  OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::FLOAT);
  spec.channelnames.clear();
  for (int k = 0; k <= set.segments(); ++k)
    for (int c = 0; c < 3; ++c) spec.channelnames.push_back(channelName(k, c));
  spec.attribute(kFormatKey, kFormatName);
  spec.attribute(kVersionKey, kVersion);
  spec.attribute(kSegmentsKey, set.segments());
  spec.attribute(kRadiusKey, float(set.radiusMm()));
  spec.attribute("compression", "zip");
  std::vector<float> knots = set.texels(), pixels(knots.size());
  for (int y = 0; y < height; ++y)
    std::copy_n(knots.data() + size_t(height - 1 - y) * size_t(width) * size_t(channels),
                size_t(width) * size_t(channels), pixels.data() + size_t(y) * size_t(width) * size_t(channels));
  // Written next to the target, then renamed: a failed write leaves no half file.
  std::string temporary = path + ".part.exr";
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create("openexr");
  if (!out) fail(SS_INTERNAL_ERROR, "OpenImageIO has no OpenEXR writer (" + OIIO::geterror() + ")");
  if (!out->open(temporary, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) || !out->close()) {
    std::string message = out->geterror();
    std::remove(temporary.c_str());
    fail(SS_INVALID_ARGUMENT, "SubEdit file '" + path + "' cannot be written (" + message + ")");
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    fail(SS_INVALID_ARGUMENT, "SubEdit file '" + path + "' cannot be written (rename failed)");
  }
}

}  // namespace subsplat
