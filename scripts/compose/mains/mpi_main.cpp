// rnav_mpi: one ensemble sharded over MPI ranks. Rank r of K runs realizations
// floor(r N / K) ... floor((r+1) N / K) - 1 - in one process (--mode inproc, the in-process
// ensemble) or with every process separate over LCM (--mode lcm: scripts/run --first-realization,
// in its own private network namespace) - into a folder of its own; the folders travel to rank 0
// (MPI_Gatherv of folder packs), which merges them (merge_shards: exact sums) into --out. The
// merged outputs are byte-identical to one run of the whole ensemble, for any K and any host
// placement. A rank that fails is named with its host and realization range; every rank says
// its range on stderr when it starts, so a rank killed outright is named by mpirun's report and
// that line.
#include "common/io/atomic_file.hpp"
#include "common/io/cli.hpp"
#include "common/io/config.hpp"
#include "scripts/compose/merge/folder_pack.hpp"
#include "scripts/compose/ensemble/inproc_ensemble.hpp"
#include "common/node/node_main.hpp"
#include "scripts/compose/merge/shard_merge.hpp"

#include <mpi.h>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstring>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <vector>

extern char** environ;

namespace {

constexpr const char* kProg = "rnav_mpi";

struct Options {
  std::string scenario, out, mode = "inproc", run_script;
  std::vector<std::string> overrides;
  long long n = 0;
  std::int64_t seed = 1;
  bool force = false;
  int die_rank = -1;  // fault injection: this rank kills itself (SIGKILL) after starting its shard
};

// Realizations [first, first + count) of rank r of k.
struct Range {
  long long first = 0, count = 0;
  std::string text() const {
    return count == 0 ? "no realization"
                      : "realizations " + std::to_string(first) + " ... " + std::to_string(first + count - 1);
  }
};
Range shard_of(long long n, int r, int k) {
  const long long a = n * r / k, b = n * (r + 1) / k;
  return {a, b - a};
}

// Run scripts/run for the shard (--mode lcm); its output goes to log. Returns its exit status.
int run_script(const Options& o, const Range& s, const std::string& out, const std::string& log) {
  std::vector<std::string> args{o.run_script, o.scenario, "--realizations", std::to_string(s.count),
                                "--first-realization", std::to_string(s.first), "--seed", std::to_string(o.seed),
                                "--out", out, "--no-plots",
                                // Each rank in a network namespace of its own, or a clear error:
                                // ranks sharing a host's multicast group would hear each other.
                                "--net", "netns"};
  for (const auto& v : o.overrides) {
    args.push_back("--set");
    args.push_back(v);
  }
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, o.run_script.c_str(), &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) throw std::runtime_error("cannot start " + o.run_script + ": " + std::strerror(rc));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw std::runtime_error("waitpid: " + std::string(std::strerror(errno)));
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string tail_of(const std::string& file, int lines) {
  std::ifstream f(file);
  std::vector<std::string> all;
  for (std::string l; std::getline(f, l);) all.push_back(l);
  std::string out;
  for (std::size_t i = all.size() > static_cast<std::size_t>(lines) ? all.size() - lines : 0; i < all.size(); ++i)
    out += "\n  | " + all[i];
  return out;
}

// This rank's shard, run into a fresh folder under $TMPDIR and packed. Throws on failure.
std::string run_shard(const Options& o, const Range& s, int rank) {
  const char* tmp = std::getenv("TMPDIR");
  std::string tmpl = std::string(tmp && *tmp ? tmp : "/tmp") + "/rnav_mpi_rank" + std::to_string(rank) + "_XXXXXX";
  if (!mkdtemp(tmpl.data())) throw std::runtime_error("cannot create a work folder " + tmpl + ": " + std::strerror(errno));
  const std::string work = tmpl, out = work + "/shard";
  struct Cleanup {
    std::string dir;
    ~Cleanup() {
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    }
  } cleanup{work};
  if (o.mode == "inproc") {
    rnav::InprocResult r;
    if (rnav::scenario_kind(o.scenario) == "uav")
      r = rnav::run_inproc_ensemble(rnav::UavScenario::load(o.scenario, o.overrides), static_cast<int>(s.count), o.seed,
                                    out, {}, static_cast<int>(s.first));
    else
      r = rnav::run_inproc_ensemble(rnav::Scenario::load(o.scenario, o.overrides), static_cast<int>(s.count), o.seed,
                                    out, {}, static_cast<int>(s.first));
    if (r.exit_code != 0) throw std::runtime_error("the in-process ensemble failed: " + r.failure);
  } else {
    const std::string log = work + "/run.log";
    const int rc = run_script(o, s, out, log);
    if (rc != 0) throw std::runtime_error(o.run_script + " exited with status " + std::to_string(rc) + ":" + tail_of(log, 6));
  }
  return rnav::pack_folder(out);
}

bool parse(int argc, char** argv, Options& o, std::ostream& help) {
  rnav::cli::Parser p(kProg, "--scenario FILE --realizations N --out DIR [--mode inproc|lcm] [options]  (under mpirun)",
                      "One ensemble sharded over MPI ranks: rank r of K runs realizations floor(rN/K) ... "
                      "floor((r+1)N/K)-1, in one process (--mode inproc) or with every process separate over LCM "
                      "(--mode lcm: scripts/run --first-realization in its own network namespace); rank 0 gathers "
                      "the shards and merges them (exact sums), so --out is byte-identical to one run of the whole "
                      "ensemble for any number of ranks. scripts/run --ranks K starts it under mpirun.");
  p.value("--scenario", "FILE", "scenario JSON file (sim/scenarios/*.json)", "required", o.scenario)
      .repeated("--set", "key=value", "override a scenario key", o.overrides)
      .value("--realizations", "N", "ensemble size, 1 ... 1e9", "required",
             [&](const std::string& v) { o.n = rnav::parse_integer("--realizations", v, 1, 1000000000); })
      .value("--seed", "S", "ensemble seed (an integer)", "1",
             [&](const std::string& v) {
               o.seed = rnav::parse_integer("--seed", v, std::numeric_limits<long long>::min(), std::numeric_limits<long long>::max());
             })
      .value("--out", "DIR", "results folder (on rank 0's host); new, empty or an earlier output unless --force", "required", o.out)
      .flag("--force", "write into --out DIR whatever it holds", o.force)
      .value("--mode", "MODE", "inproc: each rank runs its shard in one process; lcm: with every process separate over LCM", "inproc",
             [&](const std::string& v) {
               if (v != "inproc" && v != "lcm") throw rnav::ConfigError("--mode must be inproc or lcm, got '" + v + "'");
               o.mode = v;
             })
      .value("--run-script", "PATH", "with --mode lcm: the project's scripts/run", "required with --mode lcm", o.run_script)
      .value("--die-rank", "R", "fault injection: rank R kills itself (SIGKILL) once it has started its shard", "none",
             [&](const std::string& v) { o.die_rank = static_cast<int>(rnav::parse_integer("--die-rank", v, 0, INT_MAX)); });
  if (!p.parse(argc, argv, help)) return false;
  rnav::cli::require("rnav_mpi", {{"--scenario FILE", !o.scenario.empty()}, {"--realizations N", o.n != 0},
                                  {"--out DIR", !o.out.empty()}});
  if (o.mode == "lcm" && o.run_script.empty()) throw rnav::ConfigError("--mode lcm needs --run-script PATH (scripts/run)");
  if (!std::filesystem::is_regular_file(o.scenario)) throw rnav::ConfigError("--scenario " + o.scenario + ": no such file");
  if (rnav::scenario_kind(o.scenario) == "scene")
    throw rnav::ConfigError("--scenario " + o.scenario + ": a recorded scene (kind \"scene\") is not sharded over MPI ranks; "
                            "run it with scripts/run (an ensemble of 100 takes seconds)");
  return true;
}

// Rank 0's verdict broadcast to all: 0 go on, else the exit code every rank returns.
int agree(int code) {
  MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return code;
}

// Under a launcher (Open MPI, PMIx, MPICH): this process's rank, read before MPI_Init; -1 when
// the program runs alone.
long launcher_rank() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"})
    if (const char* v = std::getenv(name)) return std::strtol(v, nullptr, 10);
  return -1;
}

// What needs no MPI is answered before MPI_Init: --help, -h and --list-options always (under a
// launcher only rank 0 prints), and, when the program runs alone (not under mpirun), an error in
// the arguments. A singleton MPI_Init costs 0.3 s and leaves allocations that LeakSanitizer
// reports. Returns true, with the exit code, when the answer is given; under a launcher an
// argument error is left to the normal path (every rank agrees on it after MPI_Init).
bool answer_before_mpi(int argc, char** argv, int& code) {
  const long rank = launcher_rank();
  bool asked = false;
  for (int i = 1; i < argc; ++i)
    for (const char* h : {"--help", "-h", "--list-options"}) asked = asked || std::strcmp(argv[i], h) == 0;
  if (rank >= 0 && !asked) return false;
  Options o;
  std::ostringstream quiet;
  try {
    if (parse(argc, argv, o, rank <= 0 ? std::cout : quiet)) return false;
    code = 0;
    return true;
  } catch (const std::exception& e) {
    if (rank >= 0) return false;
    std::cerr << rnav::cli::error_line(kProg, e.what()) << "\n";
    code = dynamic_cast<const rnav::ConfigError*>(&e) ? 2 : 1;
    return true;
  }
}

// Every rank parses the same arguments (rank 0 speaks, and prepares the output folder). Returns
// the exit code (2 bad input, 1 other failure); go is false after --help or a failure.
int parse_options(int argc, char** argv, int rank, Options& o, bool& go) {
  int code = 0;
  try {
    std::ostringstream quiet;
    go = parse(argc, argv, o, rank == 0 ? std::cout : quiet);
    if (go && rank == 0) rnav::prepare_output_dir(o.out, o.force);
  } catch (const rnav::ConfigError& e) {
    if (rank == 0) std::cerr << rnav::cli::error_line(kProg, e.what()) << "\n";
    code = 2;
  } catch (const std::exception& e) {
    if (rank == 0) std::cerr << rnav::cli::error_line(kProg, e.what()) << "\n";
    code = 1;
  }
  return code;
}

// This rank's shard s run and packed (empty: no realization). On failure, or a pack beyond one
// MPI message, `failure` says why and is returned instead of the pack.
std::string run_own_shard(const Options& o, const Range& s, int rank, std::string& failure) {
  std::string pack;
  if (rank == o.die_rank) std::raise(SIGKILL);
  if (s.count > 0) {
    try {
      pack = run_shard(o, s, rank);
    } catch (const std::exception& e) {
      failure = e.what();
    }
  }
  if (!failure.empty()) pack = failure;
  if (pack.size() > static_cast<std::size_t>(INT_MAX)) {
    failure = "its outputs (" + std::to_string(pack.size()) + " bytes) exceed MPI's 2 GiB message: use more ranks";
    pack = failure;
  }
  return pack;
}

// Returns once every rank has called it, polling a non-blocking barrier every 5 ms.
void wait_for_all_ranks() {
  MPI_Request req;
  MPI_Ibarrier(MPI_COMM_WORLD, &req);
  for (int done = 0;;) {
    MPI_Test(&req, &done, MPI_STATUS_IGNORE);
    if (done) break;
    usleep(5000);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (int code = 0; answer_before_mpi(argc, argv, code)) return code;
  MPI_Init(&argc, &argv);
  int rank = 0, k = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &k);
  char host_c[MPI_MAX_PROCESSOR_NAME] = {0};
  int host_len = 0;
  MPI_Get_processor_name(host_c, &host_len);
  const std::string host(host_c, static_cast<std::size_t>(host_len));
  const auto finish = [](int code) {
    MPI_Finalize();
    return code;
  };

  // 1. Options (every rank parses the same arguments; rank 0 speaks), the output folder.
  Options o;
  bool go = false;
  int code = parse_options(argc, argv, rank, o, go);
  if (!go && code == 0) return finish(0);  // --help
  if ((code = agree(code)) != 0) return finish(code);

  // 2. This rank's shard.
  const Range s = shard_of(o.n, rank, k);
  // One write per line, so that ranks' lines do not interleave.
  std::cerr << ("mpi: rank " + std::to_string(rank) + "/" + std::to_string(k) + " on " + host + ": " + s.text() + "\n");
  const double t0 = rnav::wall_seconds();
  std::string failure;
  std::string pack = run_own_shard(o, s, rank, failure);
  const double secs = rnav::wall_seconds() - t0;

  // 3. Wait for every rank without spinning (MPI implementations busy-poll inside collectives:
  // a rank done early would take a core from the ranks still running when ranks outnumber
  // cores), then gather: status, time, host, then the packs.
  wait_for_all_ranks();
  int failed = failure.empty() ? 0 : 1, len = static_cast<int>(pack.size());
  std::vector<int> all_failed(k), lens(k);
  std::vector<double> all_secs(k);
  std::vector<char> hosts(static_cast<std::size_t>(k) * MPI_MAX_PROCESSOR_NAME);
  MPI_Gather(&failed, 1, MPI_INT, all_failed.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  MPI_Gather(&len, 1, MPI_INT, lens.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  MPI_Gather(&secs, 1, MPI_DOUBLE, all_secs.data(), 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  MPI_Gather(host_c, MPI_MAX_PROCESSOR_NAME, MPI_CHAR, hosts.data(), MPI_MAX_PROCESSOR_NAME, MPI_CHAR, 0, MPI_COMM_WORLD);
  std::vector<int> displs(k, 0);
  long long total = 0;
  if (rank == 0)
    for (int r = 0; r < k; ++r) {
      displs[r] = static_cast<int>(std::min<long long>(total, INT_MAX));
      total += lens[r];
    }
  code = rank == 0 && total > INT_MAX ? 1 : 0;
  if (code && rank == 0)
    std::cerr << rnav::cli::error_line(kProg, "the shards' outputs (" + std::to_string(total) +
                                                  " bytes) exceed MPI's 2 GiB gather: use fewer realizations per run")
              << "\n";
  if ((code = agree(code)) != 0) return finish(code);
  std::vector<char> all(rank == 0 ? static_cast<std::size_t>(total) : 0);
  MPI_Gatherv(pack.data(), len, MPI_CHAR, all.data(), lens.data(), displs.data(), MPI_CHAR, 0, MPI_COMM_WORLD);
  if (rank != 0) return finish(0);

  // 4. Rank 0: report failed ranks by name, or merge.
  const auto host_of = [&](int r) { return std::string(&hosts[static_cast<std::size_t>(r) * MPI_MAX_PROCESSOR_NAME]); };
  std::string failures;
  for (int r = 0; r < k; ++r)
    if (all_failed[r])
      failures += "\n  rank " + std::to_string(r) + " on " + host_of(r) + " (" + shard_of(o.n, r, k).text() + "): " +
                  std::string(all.data() + displs[r], static_cast<std::size_t>(lens[r]));
  if (!failures.empty()) {
    std::cerr << rnav::cli::error_line(kProg, "the run failed:" + failures) << "\n";
    return finish(1);
  }
  try {
    const double m0 = rnav::wall_seconds();
    const std::string shards_dir = o.out + "/.shards";
    std::vector<std::string> dirs;
    for (int r = 0; r < k; ++r) {
      if (shard_of(o.n, r, k).count == 0) continue;
      dirs.push_back(shards_dir + "/rank" + std::to_string(r));
      rnav::unpack_folder(std::string(all.data() + displs[r], static_cast<std::size_t>(lens[r])), dirs.back(),
                    "rank " + std::to_string(r) + " on " + host_of(r));
    }
    std::vector<char>().swap(all);
    const auto res = rnav::merge_shards(dirs, o.out);
    std::filesystem::remove_all(shards_dir);
    double slowest = 0;
    for (double x : all_secs) slowest = std::max(slowest, x);
    std::cerr << "mpi: " << k << " ranks, " << res.realizations << " realizations (" << o.mode << "); slowest rank "
              << rnav::fixed(slowest, 3) << " s, merge " << rnav::fixed(rnav::wall_seconds() - m0, 3) << " s\n";
  } catch (const std::exception& e) {
    std::cerr << rnav::cli::error_line(kProg, std::string("merging the shards failed: ") + e.what()) << "\n";
    return finish(1);
  }
  return finish(0);
}
