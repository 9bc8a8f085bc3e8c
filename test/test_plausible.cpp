// common/io/plausible.hpp: a coordinate column holding radians is named by file and column, in
// either of the two position lists; positions in degrees, near the equator and the prime
// meridian too, pass.
#include "common/io/config.hpp"
#include "common/io/plausible.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using rnav::Geodetic;
using rnav::plausible::coordinates_in_degrees;
using rnav::plausible::NamedPositions;

namespace {

constexpr double kRad = M_PI / 180;

NamedPositions named(const std::string& file, std::vector<Geodetic> g) {
  return {file + " lat_deg", file + " lon_deg", std::move(g)};
}

}  // namespace

TEST_CASE("coordinates_in_degrees: a latitude or longitude column in radians is named, in either list", "[plausible]") {
  const std::vector<Geodetic> scene{{63.44, 10.39, 15}, {63.46, 10.41, 15}, {63.45, 10.40, 15}};
  std::vector<Geodetic> lat_rad = scene, lon_rad = scene;
  for (auto& g : lat_rad) g.lat_deg *= kRad;
  for (auto& g : lon_rad) g.lon_deg *= kRad;
  CHECK_THROWS_WITH(coordinates_in_degrees(named("observer.csv", lat_rad), named("truth.csv", scene)),
                    Catch::StartsWith("observer.csv lat_deg looks like radians"));
  CHECK_THROWS_WITH(coordinates_in_degrees(named("observer.csv", scene), named("truth.csv", lon_rad)),
                    Catch::StartsWith("truth.csv lon_deg looks like radians"));
  CHECK_THROWS_AS(coordinates_in_degrees(named("a", lat_rad), named("b", scene)), rnav::ConfigError);
  std::vector<Geodetic> both = lat_rad;
  for (auto& g : both) g.lon_deg *= kRad;
  CHECK_THROWS_WITH(coordinates_in_degrees(named("truth.csv", both), named("observer.csv", scene)),
                    Catch::StartsWith("truth.csv lat_deg and truth.csv lon_deg look like radians"));
}

TEST_CASE("coordinates_in_degrees: degrees pass, near (0, 0) too, and empty lists", "[plausible]") {
  const std::vector<Geodetic> far{{-42.39, -44.37, 400}}, near_a{{-42.35, -44.16, 900}};
  CHECK_NOTHROW(coordinates_in_degrees(named("nav.csv", near_a), named("site.json", far)));
  // within a degree of the equator and the prime meridian the two units are too close to tell
  // apart: nothing is named (a scene there is neither refused)
  const std::vector<Geodetic> gulf{{0.5, 0.3, 0}}, gulf_b{{0.52, 0.31, 0}};
  CHECK_NOTHROW(coordinates_in_degrees(named("a", gulf), named("b", gulf_b)));
  CHECK_NOTHROW(coordinates_in_degrees(named("a", {}), named("b", far)));
  // another place altogether is left to plausible::near ("far away"), not called radians
  const std::vector<Geodetic> elsewhere{{1.2, 2.5, 0}};
  CHECK_NOTHROW(coordinates_in_degrees(named("a", elsewhere), named("b", far)));
}
