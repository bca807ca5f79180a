// SubEdit files in a build without OpenImageIO (SUBSPLAT_WITH_OPENIMAGEIO=OFF: a build that only
// replays scene files, which hold their profiles, on a machine without OpenImageIO; docs/BENCHMARKS.md,
// "On a GPU"). Reading or writing one is an error that says so; everything else works.
#include "material/profile_set.h"
#include "util/error.h"

namespace subsplat {

ProfileSet readSubEditFile(const std::string& path, double) {
  fail(SS_INVALID_ARGUMENT, "SubEdit file '" + path +
                                "' cannot be read: this build of subsplat has no OpenImageIO (SUBSPLAT_WITH_OPENIMAGEIO=OFF)");
}

void writeSubEditFile(const ProfileSet&, const std::string& path) {
  fail(SS_INVALID_ARGUMENT, "SubEdit file '" + path +
                                "' cannot be written: this build of subsplat has no OpenImageIO (SUBSPLAT_WITH_OPENIMAGEIO=OFF)");
}

}  // namespace subsplat
