// Heterogeneous materials: SubEdit profiles, their model (palette, segments,
// map), SubEdit files and every bad input the loader must refuse.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "material/profile_set.h"
#include "subsplat/subsplat.h"
#include "util/error.h"

namespace subsplat {
namespace {

const float kMarbleA[3] = {0.0021f, 0.0041f, 0.0071f}, kMarbleS[3] = {2.19f, 2.62f, 3.00f};
const float kSkinA[3] = {0.032f, 0.17f, 0.48f}, kSkinS[3] = {0.74f, 0.88f, 1.01f};

// width x height texels, each marble or skin by `pick`.
template <typename Pick>
ProfileSet dipoleMap(int width, int height, Pick pick, double tolerance = 0.01) {
  std::vector<float> a, s;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      bool marble = pick(x, y);
      a.insert(a.end(), marble ? kMarbleA : kSkinA, (marble ? kMarbleA : kSkinA) + 3);
      s.insert(s.end(), marble ? kMarbleS : kSkinS, (marble ? kMarbleS : kSkinS) + 3);
    }
  return ProfileSet::fromDipoles(width, height, a.data(), s.data(), 1.3, tolerance);
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(SegmentedProfile, EnergyIsTheIntegralOfTheProfile) {
  const float knots[5] = {1.0f, -0.5f, -0.4f, -3.0f, -8.0f};  // rising and falling segments
  SegmentedProfile p(knots, 4, 2.0);
  double sum = 0.0;
  constexpr int kSteps = 200000;
  for (int i = 0; i < kSteps; ++i) {
    double r = 2.0 * (i + 0.5) / kSteps;
    sum += p.value(r) * 2.0 * M_PI * r * 2.0 / kSteps;
    if (i == kSteps / 3) EXPECT_NEAR(p.energyWithin(2.0 * (i + 1) / kSteps), sum, 1e-6 * sum);
  }
  EXPECT_NEAR(p.totalEnergy(), sum, 1e-6 * sum);
  EXPECT_EQ(p.value(2.0), 0.0);
  EXPECT_NEAR(p.value(0.5), std::exp(-0.5), 1e-12);
  EXPECT_NEAR(p.radiusForEnergy(0.5), 0.0, 2.0);
  EXPECT_NEAR(p.energyWithin(p.radiusForEnergy(0.5)), 0.5 * sum, 1e-6 * sum);
}

// A dipole as a SubEdit profile: its total diffuse reflectance kept, within
// the fit tolerance, with fewer segments than it was sampled at.
TEST(ProfileSet, DipoleProfileKeepsTotalReflectanceWithFewSegments) {
  ProfileSet set = dipoleMap(1, 1, [](int, int) { return true; });
  EXPECT_EQ(set.profileCount(), 1);
  EXPECT_EQ(set.width(), 1);
  EXPECT_LE(set.info().fitError, 0.01);
  EXPECT_LT(set.segments(), set.info().sourceSegments);
  for (int c = 0; c < 3; ++c) {
    Dipole d({kMarbleA[c], kMarbleS[c], 1.3});
    EXPECT_NEAR(set.channel(0, c).totalEnergy(), d.totalReflectance(), 0.01 * d.totalReflectance()) << c;
    double r95 = set.channel(0, c).radiusForEnergy(0.95), d95 = d.radiusForEnergy(0.95);
    EXPECT_NEAR(r95, d95, 0.02 * d95) << c;
  }
}

TEST(ProfileSet, AlikeTexelsCollapseToOneProfileAndOneTexel) {
  ProfileSet set = dipoleMap(16, 8, [](int, int) { return false; });
  EXPECT_EQ(set.profileCount(), 1);
  EXPECT_EQ(set.width(), 1);
  EXPECT_EQ(set.height(), 1);
  EXPECT_EQ(set.info().sourceWidth, 16);
}

TEST(ProfileSet, ChessboardKeepsTwoProfilesAndItsMap) {
  auto marble = [](int x, int y) { return (x + y) % 2 == 0; };
  ProfileSet set = dipoleMap(8, 8, marble);
  ASSERT_EQ(set.profileCount(), 2);
  EXPECT_EQ(set.width(), 8);
  EXPECT_EQ(set.info().fitError, set.info().fitError);  // finite
  // Entry of marble texels vs skin texels, looked up by UV (texel centres, and repeating).
  int marbleEntry = set.profileAt(0.5f / 8, 0.5f / 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      int e = set.profileAt((x + 0.5f) / 8, (y + 0.5f) / 8);
      EXPECT_EQ(e == marbleEntry, marble(x, y)) << x << ", " << y;
      EXPECT_EQ(set.profileAt((x + 0.5f) / 8 + 2.0f, (y + 0.5f) / 8 - 3.0f), e);
    }
  // Skin's range is the shorter: its texels' profile holds less energy far out.
  int skinEntry = 1 - marbleEntry;
  EXPECT_LT(set.channel(skinEntry, 0).radiusForEnergy(0.95), set.channel(marbleEntry, 0).radiusForEnergy(0.95));
}

// More different profiles than a palette holds: clustered, within tolerance
// for a smooth blend, and never more than kMaxProfiles.
TEST(ProfileSet, ManyProfilesAreClusteredIntoThePalette) {
  constexpr int kSide = 64, kKnots = 33;
  std::vector<float> knots;
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      double t = (x + kSide * y) / double(kSide * kSide);  // a smooth blend of two exponentials
      for (int k = 0; k < kKnots; ++k)
        for (int c = 0; c < 3; ++c) knots.push_back(float(-k * (0.2 + 0.3 * t) - c * 0.1));
    }
  ProfileSet set = ProfileSet::fromTexels(kSide, kSide, kKnots - 1, 10.0, knots.data(), 0.01);
  EXPECT_EQ(set.info().sourceProfiles, kSide * kSide);
  EXPECT_LE(set.profileCount(), ProfileSet::kMaxProfiles);
  EXPECT_GT(set.profileCount(), 1);
  EXPECT_LE(set.info().fitError, 0.01);
  EXPECT_EQ(set.width(), kSide);
}

// More distinct media than kMaxMedia (a painted Subsurface Color holds tens of thousands): merged in
// their coefficients before any profile is evaluated, and the error reported is measured against
// the media themselves. Checked here independently: every texel's palette entry against its own
// medium's total reflectance, per channel.
TEST(ProfileSet, ManyMediaAreMergedAndTheirErrorIsMeasuredAgainstThem) {
  constexpr int kSide = 64;  // 4096 media: skin to marble across, a scale of 1 to 2 down
  std::vector<float> a, s;
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      double t = x / double(kSide - 1), scale = 1.0 + y / double(kSide - 1);
      for (int c = 0; c < 3; ++c) {
        a.push_back(float(scale * std::exp((1 - t) * std::log(kSkinA[c]) + t * std::log(kMarbleA[c]))));
        s.push_back(float(scale * std::exp((1 - t) * std::log(kSkinS[c]) + t * std::log(kMarbleS[c]))));
      }
    }
  ProfileSet set = ProfileSet::fromDipoles(kSide, kSide, a.data(), s.data(), 1.3, 0.01);
  EXPECT_LE(set.info().sourceProfiles, ProfileSet::kMaxMedia) << "merged before the profiles were evaluated";
  EXPECT_LE(set.profileCount(), ProfileSet::kMaxProfiles);
  double sum = 0.0, largest = 0.0;
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      int entry = set.profileAt((x + 0.5f) / kSide, (y + 0.5f) / kSide);
      for (int c = 0; c < 3; ++c) {
        size_t i = size_t(y * kSide + x) * 3 + size_t(c);
        double own = Dipole({a[i], s[i], 1.3}).totalReflectance();
        double e = std::abs(set.channel(entry, c).totalEnergy() / own - 1.0);
        sum += e, largest = std::max(largest, e);
      }
    }
  double mean = sum / (3.0 * kSide * kSide);
  std::printf("reported error %.4f (largest %.4f); total reflectance per texel and channel: mean %.4f, largest %.4f\n",
              set.info().fitError, set.info().maxFitError, mean, largest);
  EXPECT_LE(mean, set.info().fitError + 1e-3) << "the reported mean error covers the totals' error";
  // The reported largest is over a sample (512 of the 4096 media), so it may miss the very largest.
  EXPECT_LE(largest, 1.5 * set.info().maxFitError);
}

class SubEditFile : public ::testing::Test {
 protected:
  // One file per test: CTest runs the tests in parallel, each in a process of its own.
  void SetUp() override {
    path = ::testing::TempDir() + "subsplat_subedit_test_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".exr";
  }
  void TearDown() override { std::remove(path.c_str()); }
  // An EXR of the given channels (all `value`) and metadata, for bad-input cases.
  void writeExr(int width, int height, const std::vector<std::string>& channels, float value,
                const std::function<void(OIIO::ImageSpec&)>& metadata) {
    OIIO::ImageSpec spec(width, height, int(channels.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames = channels;
    metadata(spec);
    std::vector<float> pixels(size_t(width) * height * channels.size(), value);
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, spec) && out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) &&
                out->close());
  }
  static std::vector<std::string> knotChannels(int segments) {
    std::vector<std::string> names;
    for (int k = 0; k <= segments; ++k)
      for (char c : std::string("RGB")) names.push_back("P" + std::to_string(k) + "." + c);
    return names;
  }
  static void subEditMetadata(OIIO::ImageSpec& spec, int segments, float radius) {
    spec.attribute("subsplat:format", "SubEdit");
    spec.attribute("subsplat:version", 1);
    spec.attribute("subsplat:segments", segments);
    spec.attribute("subsplat:radius_mm", radius);
  }
  std::string loadError() { return errorOf([&] { readSubEditFile(path, 0.01); }); }
  std::string path;
};

TEST_F(SubEditFile, RoundTripKeepsEveryTexelsProfile) {
  ProfileSet set = dipoleMap(6, 4, [](int x, int y) { return x < 2 || y == 3; });
  writeSubEditFile(set, path);
  ProfileSet back = readSubEditFile(path, 0.01);
  EXPECT_EQ(back.segments(), set.segments());
  EXPECT_EQ(back.radiusMm(), set.radiusMm());
  EXPECT_EQ(back.width(), set.width());
  EXPECT_EQ(back.height(), set.height());
  EXPECT_EQ(back.profileCount(), set.profileCount());
  EXPECT_EQ(back.texels(), set.texels());  // bit for bit
  EXPECT_EQ(back.info().fitError, 0.0);
}

TEST_F(SubEditFile, TheFileIsAnOpenExrWithNamedChannelsAndMetadata) {
  ProfileSet set = dipoleMap(1, 1, [](int, int) { return true; });
  writeSubEditFile(set, path);
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  EXPECT_STREQ(in->format_name(), "openexr");
  const OIIO::ImageSpec& spec = in->spec();
  EXPECT_EQ(spec.nchannels, (set.segments() + 1) * 3);
  EXPECT_EQ(spec.get_string_attribute("subsplat:format"), "SubEdit");
  EXPECT_EQ(spec.get_int_attribute("subsplat:version"), 1);
  EXPECT_EQ(spec.get_int_attribute("subsplat:segments"), set.segments());
  EXPECT_FLOAT_EQ(spec.get_float_attribute("subsplat:radius_mm"), float(set.radiusMm()));
  bool found = false;
  for (int i = 0; i < spec.nchannels; ++i) found |= spec.channel_name(i) == "P0.G";
  EXPECT_TRUE(found);
}

TEST_F(SubEditFile, BadFilesAreRefusedWithTheirReason) {
  auto expectError = [&](const std::string& what, const std::string& needle) {
    std::string message = loadError();
    EXPECT_NE(message.find(needle), std::string::npos) << what << ": '" << message << "'";
    EXPECT_NE(message.find(path), std::string::npos) << what << ": the message names the file";
  };
  std::remove(path.c_str());
  expectError("missing", "does not exist");

  ProfileSet set = dipoleMap(4, 4, [](int x, int) { return x < 2; });
  writeSubEditFile(set, path);
  std::ifstream in(path, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size() * 2 / 3));
  }
  expectError("truncated", "truncated");
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << "P0.R, P0.G, P0.B\n1, 2, 3\n";
  }
  expectError("text", "not an image");

  std::string png = path + ".png";
  {
    OIIO::ImageSpec spec(2, 2, 3, OIIO::TypeDesc::UINT8);
    std::vector<unsigned char> pixels(12, 128);
    auto out = OIIO::ImageOutput::create(png);
    ASSERT_TRUE(out && out->open(png, spec) && out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) && out->close());
  }
  std::string pngMessage = errorOf([&] { readSubEditFile(png, 0.01); });
  std::remove(png.c_str());
  EXPECT_NE(pngMessage.find("not OpenEXR"), std::string::npos) << pngMessage;

  writeExr(2, 2, {"R", "G", "B"}, 0.0f, [](OIIO::ImageSpec&) {});
  expectError("plain EXR", "not a SubEdit file");
  writeExr(2, 2, knotChannels(2), -1.0f, [](OIIO::ImageSpec& s) {
    subEditMetadata(s, 2, 5.0f);
    s.attribute("subsplat:version", 7);
  });
  expectError("future version", "version 7");
  writeExr(2, 2, knotChannels(2), -1.0f, [](OIIO::ImageSpec& s) {
    s.attribute("subsplat:format", "SubEdit");
    s.attribute("subsplat:version", 1);
  });
  expectError("no segment count", "segment count");
  writeExr(2, 2, knotChannels(3), -1.0f, [](OIIO::ImageSpec& s) { subEditMetadata(s, 2, 5.0f); });
  expectError("channel count", "channels");
  std::vector<std::string> renamed = knotChannels(2);
  renamed[4] = "Q1.G";
  writeExr(2, 2, renamed, -1.0f, [](OIIO::ImageSpec& s) { subEditMetadata(s, 2, 5.0f); });
  expectError("missing channel", "no channel P1.G");
  writeExr(2, 2, knotChannels(2), -1.0f, [](OIIO::ImageSpec& s) { subEditMetadata(s, 0, 5.0f); });
  expectError("n = 0", "segment count");
  writeExr(2, 2, knotChannels(2), -1.0f, [](OIIO::ImageSpec& s) { subEditMetadata(s, 100000, 5.0f); });
  expectError("absurd n", "segment count");
  writeExr(2, 2, knotChannels(2), -1.0f, [](OIIO::ImageSpec& s) { subEditMetadata(s, 2, 0.0f); });
  expectError("r_s = 0", "scattering radius");
  writeExr(2, 2, knotChannels(2), -1.0f, [](OIIO::ImageSpec& s) { subEditMetadata(s, 2, -3.0f); });
  expectError("r_s < 0", "scattering radius");
  writeExr(2, 2, knotChannels(2), std::nanf(""), [](OIIO::ImageSpec& s) { subEditMetadata(s, 2, 5.0f); });
  expectError("NaN", "not a finite value");
  writeExr(2, 2, knotChannels(2), std::numeric_limits<float>::infinity(),
           [](OIIO::ImageSpec& s) { subEditMetadata(s, 2, 5.0f); });
  expectError("+inf", "not a finite value");
  writeExr(2, 2, knotChannels(2), -std::numeric_limits<float>::infinity(),
           [](OIIO::ImageSpec& s) { subEditMetadata(s, 2, 5.0f); });
  expectError("-inf", "not a finite value");
  writeExr(2, 2, knotChannels(2), 80.0f, [](OIIO::ImageSpec& s) { subEditMetadata(s, 2, 5.0f); });
  expectError("huge P", "not a finite value");
}

// A 2 x 1 SubEdit file whose texel 0 holds ln P = first and texel 1 ln P = second at every knot
// (2 segments over 5 mm), in the given pixel type.
void writeTwoTexels(const std::string& path, float first, float second, OIIO::TypeDesc type) {
  const int segments = 2, channels = (segments + 1) * 3;
  OIIO::ImageSpec spec(2, 1, channels, type);
  spec.channelnames.clear();
  for (int k = 0; k <= segments; ++k)
    for (char c : std::string("RGB")) spec.channelnames.push_back("P" + std::to_string(k) + "." + c);
  spec.attribute("subsplat:format", "SubEdit");
  spec.attribute("subsplat:version", 1);
  spec.attribute("subsplat:segments", segments);
  spec.attribute("subsplat:radius_mm", 5.0f);
  std::vector<float> pixels(size_t(2 * channels));
  std::fill(pixels.begin(), pixels.begin() + channels, first);
  std::fill(pixels.begin() + channels, pixels.end(), second);
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out && out->open(path, spec) && out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) && out->close());
}

TEST_F(SubEditFile, ProfilesThatSendOutMoreLightThanCameInAreRefusedNamingTheTexel) {
  // ln P = -5 over 5 mm carries e^-5 pi 25 = 0.53 of the light: fine. ln P = -2: 3.9 times what
  // came in, refused, naming texel (1, 0); ln P = 10 everywhere (or a file of P, not ln P, whose
  // values never go below 0) is refused with the hint.
  writeTwoTexels(path, -5.0f, -5.0f, OIIO::TypeDesc::FLOAT);
  ProfileSet fine = readSubEditFile(path, 0.01);
  EXPECT_NEAR(fine.channel(fine.profileAt(0.25f, 0.5f), 0).totalEnergy(), std::exp(-5.0) * M_PI * 25.0, 1e-3);
  writeTwoTexels(path, -5.0f, -2.0f, OIIO::TypeDesc::FLOAT);
  std::string message = loadError();
  EXPECT_NE(message.find("texel (1, 0): the R profile carries"), std::string::npos) << message;
  EXPECT_NE(message.find("cannot send out more light than came in"), std::string::npos) << message;
  EXPECT_EQ(message.find("instead of ln P"), std::string::npos) << message;
  writeTwoTexels(path, 10.0f, 10.0f, OIIO::TypeDesc::FLOAT);
  message = loadError();
  EXPECT_NE(message.find("texel (0, 0)"), std::string::npos) << message;
  EXPECT_NE(message.find("does the file hold P instead of ln P?"), std::string::npos) << message;
  writeTwoTexels(path, 0.3f, 0.5f, OIIO::TypeDesc::FLOAT);  // P = 0.3 and 0.5 written as ln P
  EXPECT_NE(loadError().find("instead of ln P"), std::string::npos);
}

TEST_F(SubEditFile, HalfFloatChannelsAreReadAsFloat) {
  // docs/SUBEDIT_FILE.md: HALF channels are accepted (read as float; ln P to about 3 digits).
  writeTwoTexels(path, -5.0f, -6.0f, OIIO::TypeDesc::HALF);
  ProfileSet set = readSubEditFile(path, 0.01);
  EXPECT_NEAR(set.channel(set.profileAt(0.25f, 0.5f), 0).totalEnergy(), std::exp(-5.0) * M_PI * 25.0, 2e-3);
  EXPECT_NEAR(set.channel(set.profileAt(0.75f, 0.5f), 2).totalEnergy(), std::exp(-6.0) * M_PI * 25.0, 2e-3);
}

// The C API: sizes and tolerances checked, handles checked, a material keeps
// its set alive after the caller released it.
TEST(ProfileSetApi, ValidatesArgumentsAndHandles) {
  std::vector<float> knots(2 * 2 * 3 * 3, -1.0f);
  SsProfileSetDesc desc{2, 5.0f, 2, 2, knots.data()};
  SsProfileSet set = nullptr;
  ASSERT_EQ(ssNewProfileSet(&desc, 0.0f, &set), SS_OK) << ssGetLastError();
  SsProfileSetInfo info{};
  ASSERT_EQ(ssGetProfileSetInfo(set, &info), SS_OK);
  EXPECT_EQ(info.profiles, 1u);
  EXPECT_EQ(info.width, 1u);
  EXPECT_GT(info.gpu_bytes, 0u);
  EXPECT_GT(info.effective_range_mm[0], 0.0f);
  EXPECT_EQ(ssReleaseProfileSet(set), SS_OK);
  EXPECT_EQ(ssGetProfileSetInfo(nullptr, &info), SS_INVALID_HANDLE);

  auto rejected = [&](SsProfileSetDesc d, float tolerance, const char* needle) {
    SsProfileSet s = reinterpret_cast<SsProfileSet>(1);
    EXPECT_EQ(ssNewProfileSet(&d, tolerance, &s), SS_INVALID_ARGUMENT) << needle;
    EXPECT_EQ(s, nullptr);
    EXPECT_NE(std::string(ssGetLastError()).find(needle), std::string::npos) << ssGetLastError();
  };
  rejected({2, 5.0f, 0, 2, knots.data()}, 0.0f, "profile map size");
  rejected({2, 5.0f, 100000, 2, knots.data()}, 0.0f, "profile map size");
  rejected({0, 5.0f, 2, 2, knots.data()}, 0.0f, "segment count");
  rejected({5000, 5.0f, 2, 2, knots.data()}, 0.0f, "segment count");
  rejected({2, 0.0f, 2, 2, knots.data()}, 0.0f, "scattering radius");
  rejected({2, std::nanf(""), 2, 2, knots.data()}, 0.0f, "scattering radius");
  rejected({2, 5.0f, 2, 2, nullptr}, 0.0f, "NULL");
  rejected({2, 5.0f, 2, 2, knots.data()}, -1.0f, "tolerance");
  rejected({1024, 5.0f, 16384, 16384, knots.data()}, 0.0f, "budget");
  knots[7] = std::numeric_limits<float>::infinity();
  rejected({2, 5.0f, 2, 2, knots.data()}, 0.0f, "not a finite value");

  EXPECT_EQ(ssLoadProfileSet(nullptr, 0.0f, &set), SS_INVALID_ARGUMENT);
  float a[3] = {0.01f, 0.01f, -1.0f}, s[3] = {1, 1, 1};
  EXPECT_EQ(ssNewProfileSetFromDipoles(1, 1, a, s, 1.3f, 0.0f, SS_PROFILE_DIPOLE, &set), SS_INVALID_ARGUMENT);
  EXPECT_NE(std::string(ssGetLastError()).find("sigma_a"), std::string::npos);
}

}  // namespace
}  // namespace subsplat
