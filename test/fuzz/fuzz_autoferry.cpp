// The Autoferry importer (estimators/diagnosis/io/autoferry_import.hpp): the input is a scenario's
// detections JSON and ground-truth JSON separated by a NUL byte; both importer modes run on it
// (multi-sensor, and the azimuth-only mode for each camera and target).
#include "estimators/diagnosis/io/autoferry_import.hpp"
#include "common/io/config.hpp"
#include "test/fuzz/fuzz_target.hpp"

#include <string>

void rnav::fuzz::run_one(const std::uint8_t* data, std::size_t size) {
  const std::string in(reinterpret_cast<const char*>(data), size);
  const std::size_t nul = in.find('\0');
  rnav::AutoferryRecords r;
  r.detections_name = "fuzz detections";
  r.ground_truth_name = "fuzz ground truth";
  r.detections = rnav::parse_json_checked(in.substr(0, nul), r.detections_name, false);
  r.ground_truth = rnav::parse_json_checked(nul == std::string::npos ? "[]" : in.substr(nul + 1),
                                            r.ground_truth_name, false);
  // Each mode on its own: a bad record for one must not hide a crash in another.
  for (const auto& [sensor, target] : {std::pair<const char*, int>{"eo", 1}, {"ir", 2}}) {
    try {
      rnav::autoferry_to_azimuth(r, sensor, target);
    } catch (const std::exception&) {
    }
  }
  rnav::autoferry_to_multi(r);
}
