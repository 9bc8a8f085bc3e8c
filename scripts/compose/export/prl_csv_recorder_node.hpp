// Node "recorder": records one realization (truth, raw plots, received nav solutions) of a
// simulation and writes it as a flight-test CSV folder (PrlFlightData), so simulated data with
// a known hidden effect goes through exactly the same reader as measured data.
#pragma once

#include "common/node/lockstep_node.hpp"
#include "estimators/diagnosis/prl_flight_data.hpp"
#include "scripts/compose/scenario/scenario.hpp"

namespace rnav {

class PrlCsvRecorderNode : public LockstepNode {
 public:
  PrlCsvRecorderNode(Bus& bus, const Scenario& sc, int realization, std::string out_dir);

 protected:
  void reset(const sim_window_t& w) override;
  int process(const sim_window_t& w) override;
  void finish(const sim_window_t& w) override;

 private:
  Scenario sc_;
  int realization_;
  std::string out_dir_;
  PrlFlightData data_;
  bool recording_ = false;
};

}  // namespace rnav
