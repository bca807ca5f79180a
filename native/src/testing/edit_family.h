// The profiles the edit basis is tested on (docs/MATERIAL_EDIT.md, "The basis"), never fitted on:
// each measured preset under each profile model, as precomputed and after the edits, and
// random media of their own seed. Linked only into what links the library's code (tests, tools).
#pragma once

#include <string>
#include <vector>

#include "material/profile_basis.h"

namespace subsplat::testing {

struct EditFamilyMember {
  std::string name;  // "Skin1 tabulated sigma_a x2 channel 2"
  OwnedProfile profile;  // cut at its material's support (SupportedProfile)
  // Whether the material's support lies within the basis's reach; an edit beyond it is
  // precomputed again, not projected (docs/MATERIAL_EDIT.md).
  bool withinReach = true;
  bool edited = false;
};

// Each preset's three channels under each model, in units of the preset's own R_P (its longest
// channel's, as precomputed), as they are and with sigma_a x 2 and with sigma_s' x 0.5 (in the
// precomputed R_P's units: the knots stay where the precomputation put them), each cut at its
// material's support.
std::vector<EditFamilyMember> presetEditFamily();
// randomMediaFamily(kEditTestSeed, count), named.
std::vector<EditFamilyMember> randomTestFamily(int count);

}  // namespace subsplat::testing
