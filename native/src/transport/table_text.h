// The text the transport tables are written in (profile_table.h, slab_table.h): whitespace-separated
// words, '#' comment lines, reals in the C locale's format whatever the host's locale is
// (std::to_chars / from_chars), so a table reads back exactly what was written and is the same
// bytes everywhere.
#pragma once

#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

namespace subsplat {

// x to `digits` significant digits (17: exactly; "inf" and "-inf" for infinities).
std::string formatReal(double x, int digits = 17);
// The text without its comment lines (those that start with '#').
std::string withoutComments(const std::string& text);

// Reads the words of a table; every failure is an Error (SS_INVALID_ARGUMENT) that names the table.
class TableWords {
 public:
  TableWords(const std::string& text, std::string table) : in_(withoutComments(text)), table_(std::move(table)) {}
  std::string word();
  void expect(const std::string& w);
  double real();              // finite, or "inf" where allowInfinity
  uint64_t count();           // a non-negative integer
  // `name`, a count (at most `most`), then that many reals.
  std::vector<double> list(const std::string& name, size_t most = 100000);
  // `name`, then n counts.
  std::vector<uint64_t> counts(const std::string& name, size_t n);
  bool done();                // nothing left
  [[noreturn]] void bad(const std::string& what) const;
  bool allowInfinity = false;

 private:
  std::istringstream in_;
  std::string table_;
};

}  // namespace subsplat
