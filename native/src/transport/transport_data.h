// The transport tables the TABULATED profile model reads, embedded at build time from
// native/src/transport/data/ (cmake/embed_files.cmake): half_space_profiles.txt (profile_table.h,
// the half-space's radial profiles by Monte Carlo) and slab_table.txt (slab_table.h, thin slabs by
// adding-doubling).
#pragma once
#include <string>

namespace subsplat {
// The named file's text, or nullptr.
const char* transportData(const std::string& name);
}  // namespace subsplat
