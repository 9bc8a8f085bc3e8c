// The fuzz targets without libFuzzer (any compiler): replay every file of the seed corpus,
// then mutate them (bit flips, byte changes, cuts, copies, insertions of boundary numbers) with
// a fixed-seed generator: a given number of mutated inputs (the same inputs on any machine,
// however loaded: a crash in the test suite replays with the same command), or for a given time.
// A crash ends the process with a signal, as it would under libFuzzer; the input that caused it
// is written first to ./crash-input (by the signal handler, with async-signal-safe calls only).
// Usage: fuzz_TARGET CORPUS_DIR [--inputs N | --seconds S (default --seconds 5)] [--seed N (default 1)]
#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

std::vector<std::uint8_t> slurp(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

const std::vector<std::uint8_t>* g_current = nullptr;  // the input being run

extern "C" void on_crash(int sig) {
  if (g_current) {
    const int fd = ::open("crash-input", O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      const ssize_t w = ::write(fd, g_current->data(), g_current->size());
      (void)w;
      ::close(fd);
    }
  }
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void run(const std::vector<std::uint8_t>& in) {
  g_current = &in;
  LLVMFuzzerTestOneInput(in.data(), in.size());
  g_current = nullptr;
}

// Tokens that reach edge cases of number and structure parsing.
const std::vector<std::string> kTokens = {"nan", "inf", "-inf", "1e308", "1e-320", "-0", "4294967297",
                                          "9223372036854775807", ",", "\n", "\"", "[", "{", "}", "]",
                                          ":", "\r\n", "1e200", "-1e200", "95", "400", "\xED\xA1\xDA\x01"};

void mutate(std::vector<std::uint8_t>& v, std::mt19937_64& rng) {
  std::uniform_int_distribution<int> kind(0, 5);
  auto pos = [&](std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n)(rng); };
  const int rounds = 1 + static_cast<int>(rng() % 4);
  for (int r = 0; r < rounds; ++r) {
    switch (kind(rng)) {
      case 0:  // flip a bit
        if (!v.empty()) v[pos(v.size() - 1)] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
        break;
      case 1:  // set a byte
        if (!v.empty()) v[pos(v.size() - 1)] = static_cast<std::uint8_t>(rng());
        break;
      case 2:  // cut the tail or a middle piece
        if (!v.empty()) {
          const std::size_t a = pos(v.size() - 1), b = std::min(v.size(), a + 1 + pos(16));
          v.erase(v.begin() + static_cast<long>(a), v.begin() + static_cast<long>(b));
        }
        break;
      case 3:  // copy a piece elsewhere
        if (v.size() > 2) {
          const std::size_t a = pos(v.size() - 2), n = 1 + pos(std::min<std::size_t>(64, v.size() - a - 1));
          const std::vector<std::uint8_t> piece(v.begin() + static_cast<long>(a), v.begin() + static_cast<long>(a + n));
          v.insert(v.begin() + static_cast<long>(pos(v.size())), piece.begin(), piece.end());
        }
        break;
      default: {  // insert a token
        const std::string& t = kTokens[rng() % kTokens.size()];
        v.insert(v.begin() + static_cast<long>(pos(v.size())), t.begin(), t.end());
      }
    }
  }
  if (v.size() > (1u << 20)) v.resize(1u << 20);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: " << argv[0] << " CORPUS_DIR [--inputs N | --seconds S] [--seed N]\n";
    return 2;
  }
  double seconds = 5;
  long inputs = -1;  // mutated inputs to run; -1: for `seconds` instead
  std::uint64_t seed = 1;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    try {
      if (a == "--seconds") seconds = std::stod(argv[i + 1]);
      else if (a == "--inputs") inputs = std::stol(argv[i + 1]);
      else if (a == "--seed") seed = std::stoull(argv[i + 1]);
      else {
        std::cerr << argv[0] << ": unknown option " << a << "\n";
        return 2;
      }
    } catch (const std::exception&) {
      std::cerr << argv[0] << ": " << a << " takes a number, got '" << argv[i + 1] << "'\n";
      return 2;
    }
  }
  if (!(seconds > 0) || inputs < -1) {
    std::cerr << argv[0] << ": --seconds must be > 0 and --inputs >= 0\n";
    return 2;
  }
  std::vector<std::vector<std::uint8_t>> corpus;
  for (const auto& e : std::filesystem::directory_iterator(argv[1]))
    if (e.is_regular_file()) corpus.push_back(slurp(e.path()));
  if (corpus.empty()) {
    std::cerr << argv[0] << ": no seed inputs in " << argv[1] << "\n";
    return 2;
  }
  for (int sig : {SIGSEGV, SIGABRT, SIGBUS, SIGFPE, SIGILL}) std::signal(sig, on_crash);
  long runs = 0;
  for (const auto& in : corpus) {
    run(in);
    ++runs;
  }
  std::mt19937_64 rng(seed);
  const auto t0 = std::chrono::steady_clock::now();
  const auto end = t0 + std::chrono::duration<double>(seconds);
  for (long k = 0; inputs >= 0 ? k < inputs : std::chrono::steady_clock::now() < end; ++k) {
    std::vector<std::uint8_t> in = corpus[rng() % corpus.size()];
    mutate(in, rng);
    run(in);
    ++runs;
  }
  const double spent_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << argv[0] << ": " << runs << " inputs (" << corpus.size() << " seeds) in " << spent_s << " s, no crash\n";
  return 0;
}
