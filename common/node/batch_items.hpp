// The samples of each batch type: its sample type and its array, so that a batch can travel as
// one message per sample (runner.wire = "sample", see LockstepNode) and be assembled again.
#pragma once

#include <rnav/aircraft_truth_batch_t.hpp>
#include <rnav/bearing_batch_t.hpp>
#include <rnav/nav_batch_t.hpp>
#include <rnav/observer_batch_t.hpp>
#include <rnav/prl_bias_batch_t.hpp>
#include <rnav/prl_error_batch_t.hpp>
#include <rnav/prl_plot_batch_t.hpp>
#include <rnav/scene_detection_batch_t.hpp>
#include <rnav/scene_observer_batch_t.hpp>
#include <rnav/scene_target_batch_t.hpp>
#include <rnav/target_truth_batch_t.hpp>
#include <rnav/tma_batch_t.hpp>

#include <vector>

namespace rnav {

/// BatchItems<B>::Sample is the sample type of batch type B; items(b) its array (b.n elements).
template <class B> struct BatchItems;

template <> struct BatchItems<aircraft_truth_batch_t> {
  using Sample = aircraft_state_t;
  static std::vector<Sample>& items(aircraft_truth_batch_t& b) { return b.states; }
};
template <> struct BatchItems<nav_batch_t> {
  using Sample = nav_solution_t;
  static std::vector<Sample>& items(nav_batch_t& b) { return b.solutions; }
};
template <> struct BatchItems<prl_plot_batch_t> {
  using Sample = prl_plot_t;
  static std::vector<Sample>& items(prl_plot_batch_t& b) { return b.plots; }
};
template <> struct BatchItems<prl_error_batch_t> {
  using Sample = prl_error_t;
  static std::vector<Sample>& items(prl_error_batch_t& b) { return b.errors; }
};
template <> struct BatchItems<prl_bias_batch_t> {
  using Sample = prl_bias_estimate_t;
  static std::vector<Sample>& items(prl_bias_batch_t& b) { return b.estimates; }
};
template <> struct BatchItems<target_truth_batch_t> {
  using Sample = target_state_t;
  static std::vector<Sample>& items(target_truth_batch_t& b) { return b.states; }
};
template <> struct BatchItems<observer_batch_t> {
  using Sample = observer_state_t;
  static std::vector<Sample>& items(observer_batch_t& b) { return b.states; }
};
template <> struct BatchItems<bearing_batch_t> {
  using Sample = bearing_t;
  static std::vector<Sample>& items(bearing_batch_t& b) { return b.bearings; }
};
template <> struct BatchItems<tma_batch_t> {
  using Sample = tma_estimate_t;
  static std::vector<Sample>& items(tma_batch_t& b) { return b.estimates; }
};

template <> struct BatchItems<scene_observer_batch_t> {
  using Sample = scene_observer_t;
  static std::vector<Sample>& items(scene_observer_batch_t& b) { return b.states; }
};
template <> struct BatchItems<scene_target_batch_t> {
  using Sample = scene_target_t;
  static std::vector<Sample>& items(scene_target_batch_t& b) { return b.states; }
};
template <> struct BatchItems<scene_detection_batch_t> {
  using Sample = scene_detection_t;
  static std::vector<Sample>& items(scene_detection_batch_t& b) { return b.detections; }
};

}  // namespace rnav
