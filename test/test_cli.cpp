// Unit tests of common/io/did_you_mean.hpp and common/io/cli.hpp: the edit distance, the nearest-name
// rule, and the option table that both parses and prints --help.
#include "common/io/cli.hpp"
#include "test/config_error.hpp"
#include "common/io/decimal.hpp"
#include "common/io/did_you_mean.hpp"

#include <catch2/catch.hpp>

#include <sstream>
#include <string>
#include <vector>

using Catch::Contains;
using Catch::StartsWith;
using Catch::EndsWith;
using rnav::ConfigError;
using rnav_test::config_error;

namespace {

// A small program's options, parsed from a list of arguments.
struct Program {
  std::string scenario, url;
  std::vector<std::string> sets, pos;
  bool realtime = false;
  double speed = 1;
  rnav::cli::Parser parser{"rnav_toy", "--scenario FILE [options]", "A toy program."};
  Program() {
    parser.value("--scenario", "FILE", "scenario JSON file", "required", scenario)
        .repeated("--set", "key=value", "override a scenario key", sets)
        .flag("--realtime", "pace to the wall clock", realtime)
        .value("--speed", "X", "simulated seconds per wall second", "1",
               [this](const std::string& v) { speed = rnav::cli::number("--speed", v, 1e-6, 1e6); })
        .value("--lcm-url", "URL", "LCM provider URL", "LCM's default", url)
        .positionals("INPUT", "input folder", [this](const std::string& v) { pos.push_back(v); });
  }
  bool parse(std::vector<std::string> args, std::ostream& out) {
    args.insert(args.begin(), "rnav_toy");
    std::vector<const char*> argv;
    for (const auto& a : args) argv.push_back(a.c_str());
    return parser.parse(static_cast<int>(argv.size()), argv.data(), out);
  }
  bool parse(std::vector<std::string> args) {
    std::ostringstream sink;
    return parse(std::move(args), sink);
  }
};

}  // namespace

TEST_CASE("edit distance counts insertions, deletions, substitutions and adjacent swaps", "[cli]") {
  CHECK(rnav::edit_distance("", "") == 0);
  CHECK(rnav::edit_distance("paper", "paper") == 0);
  CHECK(rnav::edit_distance("pape", "paper") == 1);    // insertion
  CHECK(rnav::edit_distance("papers", "paper") == 1);  // deletion
  CHECK(rnav::edit_distance("x_n", "x_m") == 1);       // substitution
  CHECK(rnav::edit_distance("raadr", "radar") == 1);   // swap
  CHECK(rnav::edit_distance("kitten", "sitting") == 3);
  CHECK(rnav::edit_distance("", "abc") == 3);
  CHECK(rnav::edit_distance("abc", "cba") == 2);
}

TEST_CASE("the nearest name is suggested only when it is near", "[cli]") {
  const std::vector<std::string> scen{"paper", "uav", "vienna_replay"};
  CHECK(rnav::closest_name("pape", scen) == "paper");
  CHECK(rnav::closest_name("uva", scen) == "uav");
  CHECK(rnav::closest_name("zzz", scen).empty());
  CHECK(rnav::closest_name("paper", scen).empty());  // itself is not a suggestion
  const std::vector<std::string> keys{"radar.x_m", "radar.z_m", "radar.antenna_height_m"};
  CHECK(rnav::closest_name("radar.x_n", keys) == "radar.x_m");
  const std::vector<std::string> opts{"--seed", "--speed", "--scenario", "--realizations"};
  CHECK(rnav::closest_name("--sed", opts) == "--seed");              // leading dashes do not count
  CHECK(rnav::closest_name("--realisations", opts) == "--realizations");
  CHECK(rnav::closest_name("--x", opts).empty());
  CHECK(rnav::did_you_mean("--sceanrio", opts) == " (did you mean '--scenario'?)");
  CHECK(rnav::did_you_mean("--verbose", opts).empty());
}

TEST_CASE("options parse from the table", "[cli]") {
  Program p;
  REQUIRE(p.parse({"--scenario", "a.json", "--set", "x=1", "--set=y=2", "--realtime", "--speed=2.5", "in"}));
  CHECK(p.scenario == "a.json");
  CHECK(p.sets == std::vector<std::string>{"x=1", "y=2"});
  CHECK(p.realtime);
  CHECK(p.speed == 2.5);
  CHECK(p.pos == std::vector<std::string>{"in"});
}

TEST_CASE("bad options are errors naming them", "[cli]") {
  CHECK(config_error([] { Program().parse({"--scenaro", "a"}); }) ==
        "unknown option '--scenaro' (did you mean '--scenario'?)");
  CHECK(config_error([] { Program().parse({"--verbose"}); }) == "unknown option '--verbose' (see rnav_toy --help)");
  CHECK(config_error([] { Program().parse({"--helpp"}); }) == "unknown option '--helpp' (did you mean '--help'?)");
  CHECK(config_error([] { Program().parse({"--scenario"}); }) == "option --scenario needs a value (FILE)");
  CHECK(config_error([] { Program().parse({"--realtime=1"}); }) == "option --realtime takes no value, got '--realtime=1'");
  CHECK_THAT(config_error([] { Program().parse({"--speed", "fast"}); }), Contains("--speed: 'fast' is not a finite number"));
  CHECK_THAT(config_error([] { Program().parse({"--speed", "0"}); }), Contains("--speed: 0 is outside"));
  rnav::cli::Parser no_pos("rnav_toy", "", "");
  const char* argv[] = {"rnav_toy", "extra"};
  CHECK(config_error([&] { std::ostringstream o; no_pos.parse(2, argv, o); }) ==
        "unexpected argument 'extra' (see rnav_toy --help)");
}

TEST_CASE("every bad option of a command line is named in one error", "[cli]") {
  CHECK(config_error([] { Program().parse({"--scenaro", "a", "--verbose", "--spede", "2"}); }) ==
        "unknown options '--scenaro' (did you mean '--scenario'?), '--verbose', '--spede' (did you mean '--speed'?)"
        " (see rnav_toy --help)");
  CHECK(config_error([] { Program().parse({"--scenaro", "a", "--spede", "2"}); }) ==
        "unknown options '--scenaro' (did you mean '--scenario'?), '--spede' (did you mean '--speed'?)");
  // unknown options, a bad value and a missing value together
  const std::string m = config_error([] { Program().parse({"--verbose", "--speed", "fast", "--scenario"}); });
  CHECK_THAT(m, StartsWith("unknown option '--verbose' (see rnav_toy --help); --speed: 'fast' is not a finite number"));
  CHECK_THAT(m, EndsWith("; option --scenario needs a value (FILE)"));
}

TEST_CASE("--help prints usage and every option with its default, --list-options the names", "[cli]") {
  for (const char* h : {"--help", "-h"}) {
    Program p;
    std::ostringstream out;
    CHECK_FALSE(p.parse({"--scenario", "a", h}, out));  // answered: the caller exits 0
    const std::string help = out.str();
    CHECK_THAT(help, StartsWith("Usage: rnav_toy --scenario FILE [options]\n"));
    CHECK_THAT(help, Contains("A toy program."));
    CHECK_THAT(help, Contains("  --scenario FILE"));
    CHECK_THAT(help, Contains("scenario JSON file (required)"));
    CHECK_THAT(help, Contains("override a scenario key (repeatable)"));
    CHECK_THAT(help, Contains("simulated seconds per wall second (default 1)"));
    CHECK_THAT(help, Contains("  INPUT"));
    CHECK(p.scenario.empty());  // nothing was parsed: help is all it did
  }
  Program p;
  std::ostringstream out;
  CHECK_FALSE(p.parse({"--list-options"}, out));
  CHECK(out.str() == "--scenario FILE\n--set key=value\n--realtime\n--speed X\n--lcm-url URL\n-h\n--help\n--list-options\n");
  // Every listed option is in the help.
  const std::string help = p.parser.help();
  std::istringstream names(out.str());
  for (std::string n; names >> n;)
    if (n[0] == '-') CHECK_THAT(help, Contains(n));
}

TEST_CASE("help text is wrapped at 100 columns", "[cli]") {
  rnav::cli::Parser p("rnav_toy", "", std::string(40, 'a') + " " + std::string(40, 'b') + " " + std::string(40, 'c'));
  std::string flag;
  p.value("--long", "X", std::string(300, ' ') + "word " + std::string(70, 'w'), "", flag);
  std::istringstream in(p.help());
  for (std::string line; std::getline(in, line);) CHECK(line.size() <= 100);
}

TEST_CASE("errors print once as PROGRAM: error: message", "[cli]") {
  CHECK(rnav::cli::error_line("rnav_clock", "bad") == "rnav_clock: error: bad");
  CHECK(rnav::cli::guarded_main("rnav_toy", [] { return 7; }) == 7);
  CHECK(rnav::cli::guarded_main("rnav_toy", []() -> int { throw ConfigError("bad input"); }) == 2);
  CHECK(rnav::cli::guarded_main("rnav_toy", []() -> int { throw std::runtime_error("disk"); }) == 1);
}

TEST_CASE("decimal numbers: the one parser of CSV cells and options", "[cli][input]") {
  double x = -1;
  std::string why;
  for (const auto& [text, value] : std::vector<std::pair<std::string, double>>{
           {"0", 0}, {"-12.5", -12.5}, {"+3", 3}, {".5", 0.5}, {"5.", 5}, {"1e3", 1000}, {"-2.5E-2", -0.025}, {"4.9e-324", 4.9e-324}}) {
    INFO(text);
    CHECK(rnav::parse_decimal(text, x, why));
    CHECK(x == value);
  }
  for (const std::string text : {"", "0x1.0p+15", "0x10", "inf", "-inf", "nan", "null", "1e", "e5", ".", "-", "1.2.3", " 1", "1 ", "1,5", "1e+"}) {
    INFO(text);
    x = 42;
    CHECK_FALSE(rnav::parse_decimal(text, x, why));
    CHECK(why == "not a decimal number");
    CHECK(x == 42);  // untouched
  }
  CHECK_FALSE(rnav::parse_decimal("1e400", x, why));
  CHECK(why == "overflows the double range");
  CHECK_FALSE(rnav::parse_decimal("-1e400", x, why));
  CHECK_THROWS_WITH(rnav::cli::number("--speed", "0x10", 0, 100), Catch::Contains("--speed: '0x10' is not a finite number (not a decimal number)"));
  CHECK_THROWS_WITH(rnav::cli::number("--speed", "1e400", 0, 1e300), Catch::Contains("overflows the double range"));
}
