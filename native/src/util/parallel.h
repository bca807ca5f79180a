// A parallel loop for the CPU reference: workers on every core, while the
// calling thread reports progress (the host's callback must run on the thread
// that called into the library) and passes on a cancel.
#pragma once

#include <cstddef>
#include <functional>

namespace subsplat {

// Returns false to stop the work.
using ProgressFunction = std::function<bool(double fraction)>;

// Runs body(begin, end) over [0, count) in chunks on all cores. Calls
// progress(base + span * done / count) from this thread about every 100 ms;
// throws Error(SS_CANCELLED) when it returns false. An exception thrown by a
// worker is rethrown here after every worker stopped.
void parallelFor(size_t count, size_t chunk, const std::function<void(size_t, size_t)>& body,
                 const ProgressFunction& progress, double base, double span);

}  // namespace subsplat
