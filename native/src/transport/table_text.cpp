#include "transport/table_text.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "util/error.h"

namespace subsplat {

std::string formatReal(double x, int digits) {
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buffer[64];
  auto result = std::to_chars(buffer, buffer + sizeof buffer, x, std::chars_format::general, digits);
  return std::string(buffer, result.ptr);
}

std::string withoutComments(const std::string& text) {
  std::istringstream lines(text);
  std::string kept;
  for (std::string line; std::getline(lines, line);)
    if (line.empty() || line[0] != '#') kept += line + '\n';
  return kept;
}

void TableWords::bad(const std::string& what) const { fail(SS_INVALID_ARGUMENT, table_ + ": " + what); }

std::string TableWords::word() {
  std::string w;
  if (!(in_ >> w)) bad("ends early");
  return w;
}

void TableWords::expect(const std::string& w) {
  std::string got = word();
  if (got != w) bad("expected '" + w + "', got '" + got + "'");
}

double TableWords::real() {
  std::string w = word();
  if (allowInfinity && w == "inf") return std::numeric_limits<double>::infinity();
  double x = 0.0;
  auto result = std::from_chars(w.data(), w.data() + w.size(), x);  // the C locale's format
  if (result.ec != std::errc() || result.ptr != w.data() + w.size() || !std::isfinite(x)) bad("bad number '" + w + "'");
  return x;
}

uint64_t TableWords::count() {
  std::string w = word();
  char* end = nullptr;
  if (w.empty() || w[0] == '-') bad("bad count '" + w + "'");
  uint64_t c = std::strtoull(w.c_str(), &end, 10);
  if (*end != '\0') bad("bad count '" + w + "'");
  return c;
}

std::vector<double> TableWords::list(const std::string& name, size_t most) {
  expect(name);
  uint64_t n = count();
  if (n > most) bad("too many " + name);
  std::vector<double> v(n);
  for (double& x : v) x = real();
  return v;
}

std::vector<uint64_t> TableWords::counts(const std::string& name, size_t n) {
  expect(name);
  std::vector<uint64_t> v(n);
  for (uint64_t& c : v) c = count();
  return v;
}

bool TableWords::done() {
  std::string w;
  return !(in_ >> w);
}

}  // namespace subsplat
