// Under AddressSanitizer (build-san/, scripts/run_tests.sh): LeakSanitizer's check runs after the
// last test, while the process is whole, instead of at its exit. At exit it met threads of Mesa's
// shader disk cache and its own tracer crashed (signal 11) after tests that had passed (docs/CI.md).
// __lsan_do_leak_check runs the check once; the one at exit is then skipped.
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SUBSPLAT_LEAK_CHECK 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define SUBSPLAT_LEAK_CHECK 1
#endif

#ifdef SUBSPLAT_LEAK_CHECK
#include <gtest/gtest.h>
#include <sanitizer/lsan_interface.h>

namespace {

class LeakCheckAfterTheTests : public ::testing::Environment {
 public:
  void TearDown() override { __lsan_do_leak_check(); }
};

const ::testing::Environment* const registered = ::testing::AddGlobalTestEnvironment(new LeakCheckAfterTheTests);

}  // namespace
#endif
