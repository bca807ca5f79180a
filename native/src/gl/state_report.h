// The OpenGL state a host such as Blender relies on, as text: one "name=value" line per item.
// Queried independently of StateGuard (which saves and restores part of it), so that a test
// can compare the state before and after a call and see what the library left changed.
#pragma once

#include <string>

namespace subsplat::gl {

std::string describeState();

}  // namespace subsplat::gl
