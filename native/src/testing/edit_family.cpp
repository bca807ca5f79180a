#include "testing/edit_family.h"

#include <algorithm>

#include "material/splat_kernel.h"
#include "material/transport_model.h"
#include "testing/procedural.h"

namespace subsplat::testing {

std::vector<EditFamilyMember> presetEditFamily() {
  std::vector<EditFamilyMember> family;
  const char* edits[] = {"", " sigma_a x2", " sigma_s' x0.5"};
  for (const PresetMedium& preset : kPresetMedia)
    for (int model : {kProfileDipole, kProfileTabulated}) {
      double range = 0.0;  // mm: the precomputed material's R_P
      for (int c = 0; c < 3; ++c) {
        DipoleChannel channel{preset.sigmaA[c], preset.sigmaSPrime[c], 1.3};
        range = std::max(range, makeMediumProfile(channel, model)->radiusForEnergy(SplatKernel::kEffectiveRangeEnergy));
      }
      for (int edit = 0; edit < 3; ++edit) {
        std::shared_ptr<const RadialProfile> channels[3];
        double support = 0.0;  // mm: the edited material's
        for (int c = 0; c < 3; ++c) {
          DipoleChannel channel{preset.sigmaA[c] * (edit == 1 ? 2.0 : 1.0),
                                preset.sigmaSPrime[c] * (edit == 2 ? 0.5 : 1.0), 1.3};
          channels[c] = makeMediumProfile(channel, model);
          support = std::max(support, channels[c]->radiusForEnergy(SplatKernel::kSupportEnergy));
        }
        for (int c = 0; c < 3; ++c) {
          EditFamilyMember m;
          m.name = std::string(preset.name) + (model == kProfileDipole ? " dipole" : " tabulated") + edits[edit] +
                   " channel " + std::to_string(c);
          m.profile.profile = std::make_shared<SupportedProfile>(channels[c], support);
          m.profile.mmPerUnit = range;
          m.withinReach = support / range <= kEditReach;
          m.edited = edit != 0;
          family.push_back(std::move(m));
        }
      }
    }
  return family;
}

std::vector<EditFamilyMember> randomTestFamily(int count) {
  std::vector<EditFamilyMember> family;
  std::vector<OwnedProfile> media = randomMediaFamily(kEditTestSeed, count);
  for (size_t i = 0; i < media.size(); ++i) {
    const auto* cut = dynamic_cast<const SupportedProfile*>(media[i].profile.get());
    family.push_back({"test medium " + std::to_string(i), media[i], cut->support() / media[i].mmPerUnit <= kEditReach});
  }
  return family;
}

}  // namespace subsplat::testing
