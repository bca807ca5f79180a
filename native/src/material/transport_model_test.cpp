// The TABULATED profile model on the CPU (material/transport_model.h): its totals and angles
// against Chandrasekhar's H-function, its thin slabs against adding-doubling and the slab Monte
// Carlo, energy, and the embedded tables against the programs that made them.
#include "material/transport_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "transport/adding_doubling.h"
#include "transport/hfunction.h"
#include "transport/profile_table.h"
#include "transport/slab_monte_carlo.h"
#include "transport/slab_table.h"
#include "transport/transport_data.h"

namespace subsplat {
namespace {

// A medium of albedo a with sigma_t = 1 per mm: lengths in mm are mean free paths.
DipoleChannel channelOf(double a, double eta = 1.0) { return {1.0 - a, a, eta}; }
TransportTables tablesOf(double a) { return TransportTables({channelOf(a), channelOf(a), channelOf(a)}); }

const double kAlbedos[] = {0.02, 0.3, 0.7, 0.88, 0.93, 0.97, 0.99, 0.996, 0.9993, 0.99995};

TEST(TabulatedModel, ProfileTotalIsTheExactHalfSpaceAlbedo) {
  for (double a : kAlbedos) {
    TabulatedProfile p(channelOf(a));
    double exact = halfSpaceAlbedo(HFunction(a), 1.0);
    EXPECT_NEAR(p.totalEnergy() / exact, 1.0, 2e-7) << "albedo " << a;  // halfSpaceAlbedoAtNormalIncidence
    EXPECT_NEAR(p.energyWithin(1e6) / p.totalEnergy(), 1.0, 1e-9) << "albedo " << a;  // the whole shape
    double previous = 0.0;
    for (double r = 1e-4; r < 1e4; r *= 1.3) {  // energy grows, P stays finite and non-negative
      double e = p.energyWithin(r);
      EXPECT_GE(e, previous - 1e-15) << "albedo " << a << " r " << r;
      EXPECT_TRUE(std::isfinite(p.value(r)) && p.value(r) >= 0.0);
      previous = e;
    }
  }
  // eta > 1: the dipole's boundary factor; a = 0 reflects nothing.
  EXPECT_NEAR(tabulatedTotalReflectance(0.9, 1.3) / tabulatedTotalReflectance(0.9, 1.0),
              dipoleTotalReflectance(0.9, 1.3) / dipoleTotalReflectance(0.9, 1.0), 1e-12);
  EXPECT_EQ(TabulatedProfile(channelOf(0.0)).totalEnergy(), 0.0);
}

// R(1) from its nodes against the H-function solved at the albedo itself, at 600 albedos from 1e-3
// to 1 - 1e-7 (dense towards 1): within 3e-9, and 2e-7 of R(1) (the largest, near a = 0, where R(1)
// is a few 1e-5).
TEST(TabulatedModel, NormalIncidenceAlbedoIsTheHFunctions) {
  double worst = 0.0, worstRelative = 0.0;
  for (int t = 0; t < 600; ++t) {
    double a = t < 300 ? (t + 0.37) / 300.0 : 1.0 - std::pow(10.0, -1.0 - 6.0 * (t - 300) / 300.0);
    double exact = halfSpaceAlbedo(HFunction(a), 1.0), tabulated = halfSpaceAlbedoAtNormalIncidence(a);
    worst = std::max(worst, std::abs(tabulated - exact));
    worstRelative = std::max(worstRelative, std::abs(tabulated - exact) / exact);
  }
  EXPECT_LT(worst, 3e-9);
  EXPECT_LT(worstRelative, 2e-7);
  EXPECT_EQ(halfSpaceAlbedoAtNormalIncidence(0.0), 0.0);
  EXPECT_EQ(halfSpaceAlbedoAtNormalIncidence(1.0), 1.0);
}

// Between the table's albedos the shape is interpolated: at albedos the table does not hold, the
// energy within each radius agrees with a Monte Carlo run of its own (other seed) to 2 %.
TEST(TabulatedModel, ProfileAtAnAlbedoBetweenTheTablesIsTheMonteCarlos) {
  for (double a : {0.75, 0.93, 0.996}) {
    SlabSettings s;
    s.albedo = a;
    s.paths = 200000;
    s.seed = 7;
    s.radiusEdges = {0.0, 0.3, 1.0, 3.0, 10.0, 30.0};
    s.threads = 2;
    SlabTallies t = simulateSlab(s);
    TabulatedProfile p(channelOf(a));
    double cumulative = 0.0;
    for (size_t k = 0; k + 1 < s.radiusEdges.size(); ++k) {
      cumulative += t.fraction(t.reflectedByRadius[k]);
      double model = p.energyWithin(s.radiusEdges[k + 1]);
      EXPECT_NEAR(model / cumulative, 1.0, 0.02) << "albedo " << a << " within " << s.radiusEdges[k + 1] << " mfp";
    }
  }
}

// A sun over a half-space: E R(mu0) / R(1) through the profile (total R(1)), times the exit factor
// over pi, is Chandrasekhar's a E H(mu0) H(mu) / (4 pi (mu0 + mu)).
TEST(TabulatedModel, AngularFactorsAreTheHFunctions) {
  for (double a : kAlbedos) {
    TransportTables t = tablesOf(a);
    HFunction h(a);
    double r1 = halfSpaceAlbedo(h, 1.0);
    for (double mu0 : {1.0, 0.7, 0.5, 0.17, 0.05})
      for (double mu : {1.0, 0.8, 0.4, 0.1}) {
        double model = r1 * t.incidence(0, double(INFINITY), mu0) * t.exit(0, mu0, mu) / M_PI;
        EXPECT_NEAR(model / halfSpaceReflectedRadiance(h, mu0, mu), 1.0, 3e-3)
            << "albedo " << a << " mu0 " << mu0 << " mu " << mu;
      }
  }
}

// The forward shift's length (docs/TRANSPORT.md, "The entry's forward shift"): the mean distance
// along the beam of the first collision of the reflected light is 1 + mu0 R'(mu0) / R(mu0), R'
// taken here from the H-function itself by a central difference, the tables' from their samples.
TEST(TabulatedModel, BeamCentroidIsTheHFunctions) {
  double worst = 0.0;
  for (double a : kAlbedos) {
    TransportTables t = tablesOf(a);
    HFunction h(a);
    for (double mu0 : {0.02, 0.1, 0.3, 0.5, 0.8, 0.98}) {
      const double step = 1e-4;
      double derivative = (halfSpaceAlbedo(h, mu0 + step) - halfSpaceAlbedo(h, mu0 - step)) / (2.0 * step);
      double exact = 1.0 + mu0 * derivative / halfSpaceAlbedo(h, mu0);
      double model = t.beamCentroid(0, mu0);
      worst = std::max(worst, std::abs(model - exact));
      EXPECT_NEAR(model, exact, 2e-3) << "albedo " << a << " mu0 " << mu0;
      EXPECT_GT(model, 0.0);
      EXPECT_LE(model, 1.0 + 1e-9);  // escaping favours the shallow collisions
    }
  }
  std::printf("beam centroid: worst difference from the H-function's %.2e mfp\n", worst);
  EXPECT_DOUBLE_EQ(tablesOf(0.0).beamCentroid(0, 0.5), 1.0);
}

// ... and is where the reflected light leaves: an analog walk of its own in the half-space, the
// beam entering at the origin along +x at mu0; after the first collision the walk is isotropic, so
// the mean exit x of the reflected paths is the centroid's distance times sin theta (4 standard
// errors).
TEST(TabulatedModel, ReflectedLightIsCentredAheadOfTheEntryByTheBeamCentroid) {
  std::mt19937_64 random(19);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  auto flight = [&] { return -std::log(1.0 - uniform(random)); };
  for (double a : {0.7, 0.95})
    for (double mu0 : {0.2, 0.6}) {
      double sinTheta = std::sqrt(1.0 - mu0 * mu0);
      double sum = 0.0, sum2 = 0.0;
      int reflected = 0;
      for (int path = 0; path < 100000; ++path) {
        double s = flight(), x = s * sinTheta, z = s * mu0;  // z: depth
        while (uniform(random) < a) {
          double w = 2.0 * uniform(random) - 1.0, phi = 2.0 * M_PI * uniform(random), l = flight();
          double along = std::sqrt(std::max(1.0 - w * w, 0.0)) * std::cos(phi);
          if (z + l * w < 0.0) {  // leaves through the surface
            x += along * (z / -w);
            sum += x, sum2 += x * x, ++reflected;
            break;
          }
          x += along * l, z += l * w;
        }
      }
      double mean = sum / reflected, error = std::sqrt((sum2 / reflected - mean * mean) / reflected);
      double model = tablesOf(a).beamCentroid(0, mu0) * sinTheta;
      EXPECT_NEAR(mean, model, 4.0 * error) << "albedo " << a << " mu0 " << mu0;
    }
}

// The exit factor spreads exactly what came in: 2 int X mu dmu = 1.
TEST(TabulatedModel, ExitFactorKeepsTheExitance) {
  MuQuadrature q = gaussLegendreInSqrtMu(64);
  for (double a : kAlbedos) {
    TransportTables t = tablesOf(a);
    for (double mu0 : {1.0, 0.5, 0.1}) {
      double sum = 0.0;
      for (size_t i = 0; i < q.mu.size(); ++i) sum += 2.0 * q.weight[i] * q.mu[i] * t.exit(0, mu0, q.mu[i]);
      EXPECT_NEAR(sum, 1.0, 3e-3) << "albedo " << a << " mu0 " << mu0;
    }
  }
}

// Thicknesses, albedos and cosines between the table's nodes against adding-doubling solved there:
// the reflectance within 3 %, the transmitted radiance within 7 % (the worst, 6 %: a = 0.5 through
// 6 mfp at mu0 = 0.6, where T is e^-10 of the beam and bends most between the mu0 nodes).
TEST(TabulatedModel, ThinSlabsAreAddingDoublings) {
  for (double a : {0.5, 0.93, 0.996})
    for (double tau : {0.3, 1.7, 6.0})
      for (double mu0 : {1.0, 0.6}) {
        TransportTables t = tablesOf(a);
        SlabSolution s = solveSlabByAddingDoubling(a, tau, mu0);
        double r1 = halfSpaceAlbedo(HFunction(a), 1.0);
        EXPECT_NEAR(t.incidence(0, tau, mu0) * r1 / s.reflectance, 1.0, 0.03)
            << "albedo " << a << " tau " << tau << " mu0 " << mu0;
        for (size_t i = 0; i < s.mu.size(); i += 5)
          if (s.mu[i] > 0.05)
            EXPECT_NEAR(t.transmitted(0, tau, mu0, s.mu[i]) / s.transmittedRadiance[i], 1.0, 0.07)
                << "albedo " << a << " tau " << tau << " mu0 " << mu0 << " mu " << s.mu[i];
      }
}

// The repo's own one-dimensional Monte Carlo, within 4 standard errors (and 3 %) in exit-cosine
// bins of the light scattered through.
TEST(TabulatedModel, ThinSlabTransmissionIsTheMonteCarlos) {
  for (double tau : {0.5, 2.0, 5.0}) {
    SlabSettings s;
    s.albedo = 0.95;
    s.thickness = tau;
    s.paths = 200000;
    s.cosineBins = 4;
    s.seed = 3;
    s.threads = 2;
    SlabTallies mc = simulateSlab(s);
    TransportTables t = tablesOf(s.albedo);
    for (int b = 0; b < s.cosineBins; ++b) {
      double m0 = double(b) / s.cosineBins, m1 = double(b + 1) / s.cosineBins;
      // The model's mean radiance over the bin, mu-weighted as the tally.
      double sum = 0.0, weight = 0.0;
      for (int k = 0; k < 200; ++k) {
        double mu = m0 + (m1 - m0) * (k + 0.5) / 200;
        sum += mu * t.transmitted(0, tau, 1.0, mu);
        weight += mu;
      }
      double model = sum / weight, measured = mc.radianceInCosineBin(mc.transmittedByCosine, b);
      double error = measured / std::sqrt(double(std::max<uint64_t>(mc.transmittedByCosine[size_t(b)], 1)));
      EXPECT_LT(std::abs(model - measured), std::max(4.0 * error, 0.03 * measured)) << "tau " << tau << " bin " << b;
    }
  }
}

// No albedo, thickness or angle gives more light out of both faces than came in.
TEST(TabulatedModel, NoSlabSendsOutMoreLightThanCameIn) {
  MuQuadrature q = gaussLegendreInSqrtMu(32);
  for (double a : {0.0, 0.3, 0.9, 0.99, 0.9999, 1.0})
    for (double tau : {0.01, 0.1, 0.5, 1.0, 3.0, 10.0, 100.0, 1e4, double(INFINITY)})
      for (double mu0 : {1.0, 0.5, 0.1}) {
        TransportTables t = tablesOf(a);
        double r1 = a > 0.0 ? halfSpaceAlbedo(HFunction(a), 1.0) : 0.0;
        double reflected = r1 * t.incidence(0, tau, mu0), through = 0.0;
        for (size_t i = 0; i < q.mu.size(); ++i)
          through += 2.0 * M_PI * q.weight[i] * q.mu[i] * t.transmitted(0, tau, mu0, q.mu[i]);
        double unscattered = std::isinf(tau) ? 0.0 : std::exp(-tau / mu0);
        // What the model renders (the unscattered beam is not rendered: a delta)...
        EXPECT_LE(reflected + through, 1.0 + 1e-6) << "albedo " << a << " tau " << tau << " mu0 " << mu0;
        // ... and with the beam that went straight through: the nodes hold exactly 1 at a = 1;
        // between them interpolation adds at most 2 % (small mu0 and tau, where e^(-tau/mu0) bends).
        EXPECT_LE(reflected + through + unscattered, 1.02) << "albedo " << a << " tau " << tau << " mu0 " << mu0;
        EXPECT_GE(reflected, 0.0);
        EXPECT_GE(through, 0.0);
      }
}

// The embedded tables are what their programs make: slab entries solved again by adding-doubling
// (to the 6 digits written), and one half-space albedo's Monte Carlo run again (the same counts:
// every entry has its own paths' random numbers).
TEST(TabulatedModel, EmbeddedTablesAreWhatTheProgramsMake) {
  const char* slabText = transportData("slab_table.txt");
  ASSERT_NE(slabText, nullptr);
  SlabTable slab = readSlabTable(slabText);
  SlabTable grid = slabTableGrid();
  ASSERT_EQ(slab.albedos, grid.albedos);
  ASSERT_EQ(slab.thicknesses, grid.thicknesses);
  ASSERT_EQ(slab.cosines, grid.cosines);
  for (size_t a : {size_t(3), size_t(11), size_t(20)})
    for (size_t k : {size_t(2), size_t(9), size_t(15)}) {
      size_t m0 = (a + k) % slab.cosines.size();
      SlabSolution s = solveSlabByAddingDoubling(slab.albedos[a], slab.thicknesses[k], slab.cosines[m0]);
      EXPECT_NEAR(slab.reflectance[slab.index(a, k, m0)], s.reflectance, 1e-5 * s.reflectance + 1e-12);
    }
  const char* profileText = transportData("half_space_profiles.txt");
  ASSERT_NE(profileText, nullptr);
  ProfileTable table = readProfileTable(profileText);
  ProfileTableSpec spec = halfSpaceProfileTableSpec();
  EXPECT_EQ(table.spec.albedos, spec.albedos);
  ProfileTableSpec one = spec;
  size_t which = 5;  // a = 0.5
  one.albedos = {spec.albedos[which]};
  one.threads = 2;
  ProfileTable again = makeProfileTable(one);
  EXPECT_EQ(again.at(0, 0).reflectedByRadius, table.at(which, 0).reflectedByRadius);
  EXPECT_EQ(again.at(0, 0).reflected, table.at(which, 0).reflected);
  // The normal-incidence albedo's nodes: the file is what solveNormalIncidenceAlbedoNodes writes,
  // to the bit (17 digits round-trip a double).
  const char* nodesText = transportData("normal_incidence_albedo.txt");
  ASSERT_NE(nodesText, nullptr);
  EXPECT_EQ(std::string(nodesText), writeNormalIncidenceAlbedoNodes(solveNormalIncidenceAlbedoNodes()));
}

TEST(TabulatedModel, SideWeightIsASmoothStepFromFacingApartToFacingAlike) {
  EXPECT_EQ(sideWeight(-1.0), 0.0);
  EXPECT_EQ(sideWeight(-0.5), 0.0);
  EXPECT_DOUBLE_EQ(sideWeight(0.0), 0.5);
  EXPECT_EQ(sideWeight(0.5), 1.0);
  EXPECT_EQ(sideWeight(1.0), 1.0);
}

}  // namespace
}  // namespace subsplat
