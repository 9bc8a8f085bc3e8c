#include "atomic_file.hpp"

#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace rnav {

void write_file_atomic(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string tmp = dir + "/." + name + ".partial", dst = dir + "/" + name;
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) throw std::runtime_error("cannot write " + tmp);
    f << text;
    f.flush();
    if (!f) throw std::runtime_error("error writing " + tmp);
  }
  if (std::rename(tmp.c_str(), dst.c_str()) != 0) throw std::runtime_error("cannot rename " + tmp);
}

std::string fixed(double x, int prec) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", prec, x);
  return b;
}

}  // namespace rnav
