// Node "logger": joins, per plot, the truth (TRUTH_AIRCRAFT), the raw plot (PRL_APOI), the
// injected error (TRUTH_PRL_ERROR), the compensated plot (PRL_TOI) and the bias estimate
// (PRL_BIAS); keeps a realization until the clock moves past it, then adds it to PrlStats; on
// FINISH writes the result files (ensemble_logger_node.hpp). A plot missing any part at the end
// of its realization, or an ensemble short of realizations, is an error: nothing is averaged
// silently over less.
#pragma once

#include "loggers/ensemble_logger_node.hpp"
#include "loggers/prl_stats.hpp"

#include <rnav/prl_bias_estimate_t.hpp>
#include <rnav/prl_error_t.hpp>
#include <rnav/prl_plot_t.hpp>

#include <map>

namespace rnav {

class PrlLoggerNode : public EnsembleLoggerNode<PrlStats, std::vector<PlotErrors>> {
 public:
  /// @param scenario_json  the effective scenario's text, written as scenario.json
  /// @param out_dir        where FINISH writes the result files; "" writes nothing
  PrlLoggerNode(Bus& bus, const LoggerOptions& o, const SiteContext& site, std::string scenario_json,
                std::string out_dir);

 protected:
  void start_realization(const sim_window_t& w) override;
  int process(const sim_window_t& w) override;

 private:
  LoggerOptions o_;
  Eigen::Isometry3d T_L_R_;  // radar frame R -> landing frame L
  std::map<std::int64_t, Eigen::Vector3d> truth_;  // utime -> p_TA_L
  std::map<std::int64_t, prl_plot_t> apoi_, toi_;   // plot_id -> plot
  std::map<std::int64_t, prl_error_t> err_;
  std::map<std::int64_t, prl_bias_estimate_t> bias_;
};

}  // namespace rnav
