// libFuzzer target: the SubEdit file loader (ssLoadProfileSet) on arbitrary bytes. Every input
// must load or fail with a status and a message; nothing may crash, hang or leak.
//   fuzz_subedit_file -max_total_time=60 WORK_CORPUS native/fuzz/corpus/subedit
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "subsplat/subsplat.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = "/tmp/subsplat_fuzz_subedit_" + std::to_string(getpid()) + ".exr";
  FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) return 0;
  std::fwrite(data, 1, size, file);
  std::fclose(file);
  SsProfileSet set = nullptr;
  if (ssLoadProfileSet(path.c_str(), 0.0f, &set) == SS_OK) {
    SsProfileSetInfo info;
    if (ssGetProfileSetInfo(set, &info) != SS_OK) __builtin_trap();
    ssReleaseProfileSet(set);
  } else if (set != nullptr || ssGetLastError()[0] == '\0') {
    __builtin_trap();  // a failure leaves no handle and says why
  }
  return 0;
}
