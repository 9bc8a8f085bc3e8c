// The effect-search engine: what does the nominal model get wrong in these observations?
// It knows nothing of radars or cameras. An adapter states the problem:
//   - observations: residuals y = measured - reference prediction, grouped in channels (one
//     sensor x target x quantity each, in time order), each with its nominal noise sigma;
//   - nuisance columns (the nominal model's own free parameters, e.g. a constant bias);
//   - a catalogue of candidate effects: regressor columns per observation, each with a scope
//     (sensor, target, both or neither), scanned over a grid (a step time, a period, a
//     manoeuvre time) or not (a physical one-parameter cause).
// The engine then:
//   1. identifies each channel's noise model first (noise_id.hpp: white, Gauss-Markov, their sum,
//      outlier flags) and tests every mean effect under it (GLS through the innovations form);
//   2. forward selection: the entry with the smallest Bonferroni-adjusted p-value enters while
//      that p is below alpha. Familywise error: alpha is split equally over the catalogue entries
//      (m = catalogue size + the noise tests) and a scanned entry splits its share over its grid
//      (look-elsewhere), so under the nominal model P(any effect named) <= alpha; a scanned entry
//      thus pays for its scan and a physical entry that explains the same residual wins;
//   3. checks each chosen effect given the others under every noise model the data allow (the
//      least 2 log LR over the channels' noise confidence sets: a slow correlation is poorly
//      determined in a short record, and a plug-in noise estimate lets slow noise pass as an
//      effect), drops those that no longer pass, re-identifies the noise with the rest and
//      repeats until the choice settles;
//   4. reports each effect's estimate and SE (GLS, scale from the whitened residuals), its
//      evidence (2 log LR without it, adjusted p, delta BIC), what it is confounded with (the
//      canonical correlation of its whitened columns with another entry's given the rest of the
//      model, or another entry that explains the residual as well), detection limits (the size
//      detected with probability `power` at the per-entry level, from the Fisher information),
//      noise findings (noise_scale against the nominal sigma, correlated_noise, and outliers only
//      when the outlier mixture raises the out-of-sample likelihood), the out-of-sample gain (fit
//      on the estimation frames, score the rest), residual correlations left unexplained, and
//      answers to scope questions (which of several explanations the likelihood supports).
#pragma once

#include "estimators/model_id/noise_id.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace rnav {

namespace search_detail {
class NoiseMemo;
}

/// Where an effect acts: a sensor, a target's reference, both, or everything (empty = null).
struct Scope {
  std::string sensor, target;
  /// The one recording the entry belongs to, when several are diagnosed together; empty: every
  /// recording (hardware: one value wherever the sensor or target appears).
  std::string recording{};
  std::string label() const;  ///< "sensor radar", "target 1", "radar:1", "common"; " in REC" for one recording
};

struct Channel {
  std::string name;           ///< e.g. "radar:1:range"
  std::string sensor, target; ///< scope keys (may be empty)
  std::string unit;           ///< unit of y, e.g. "m", "rad"
  double nominal_sigma = 1;   ///< the nominal model's white noise sigma [unit], > 0
  /// The nominal model's own correlated noise, if it has one (e.g. a navigation solution's
  /// Gauss-Markov error seen through the measurement): sigma [unit] (0: none, >= 0) and its
  /// correlation time [s] (> 0 when sigma > 0). correlated_noise is then named only where the
  /// data depart from it, and noise_scale compares against the nominal total variance. The
  /// sigma is the RMS over the channel's observations when Problem::nominal_corr_gain gives the
  /// component a gain per observation (its projection changes along the geometry).
  double nominal_corr_sigma = 0;
  double nominal_corr_tau_s = 0;
  /// Channels of one group ("" none) are one quantity of one sensor on different targets: the
  /// constant offsets no named effect explains on them (a hull's echo point, an antenna on the
  /// hull) are taken as a random effect across the targets (SearchResult::offsets). E.g. "radar:range".
  std::string offset_group{};
  double nominal_var() const { return nominal_sigma * nominal_sigma + nominal_corr_sigma * nominal_corr_sigma; }
  /// The nominal correlated component's share of nominal_var(), capped at 0.999 (noise_model.hpp's mu).
  double nominal_share() const { return std::min(0.999, nominal_corr_sigma * nominal_corr_sigma / nominal_var()); }
};

/// A catalogue entry's columns computed and checked once (Candidate::kept_columns).
struct KeptColumns {
  std::vector<Eigen::MatrixXd> columns;    ///< per grid point v: Candidate::columns(v)
  std::vector<std::vector<char>> touches;  ///< per grid point v and channel: not all 0 on the channel's observations
};

struct Candidate {
  std::string name;                 ///< catalogue name, e.g. "time_offset"
  Scope scope;
  std::vector<std::string> params;  ///< parameter names with their unit, one per column
  std::string signature;            ///< what its columns scale with (for the confounding note)
  std::string scan_param;           ///< name of the scanned value ("t_s", "period_s"); empty: not scanned
  std::vector<double> scan;         ///< the scan grid (empty: not scanned)
  /// Columns of grid point v (0 when not scanned): n_obs x params.size(), zero outside its scope.
  std::function<Eigen::MatrixXd(std::size_t v)> columns;
  /// columns(v) for every v, computed and checked once (none: computed on each call). Set by
  /// the limits by injection for their searches, whose catalogue is the same in every one.
  std::shared_ptr<const KeptColumns> kept_columns{};
  /// Only an alternative of a scope question (e.g. a hardware effect's per-recording values):
  /// never selected, tested or given a limit on its own, and not in the familywise count.
  bool scope_only = false;
  /// An entry that claims one value in several replicates (hardware in several recordings): its
  /// scope_only copies, one per replicate, same grid. It enters only when the replicates agree
  /// (replication.hpp); empty: no such claim.
  std::vector<std::size_t> replicates{};
  /// With replicates: they must also agree with one value (Cochran's Q of their values not
  /// significant at alpha), not only have a significant mean. For an offset whose per-replicate
  /// departures do not average out (every ship's echo comes from its near side, so every
  /// target's range offset is short): a mean over such replicates is no common cause.
  bool one_value = false;
  /// A shape in time (a drift) rather than a physical cause; every scanned entry (a step, a
  /// period, a manoeuvre time) is one as well (is_shape). Of two entries that explain the same
  /// residual, a shape replaces a physical cause only by more than explaining as well
  /// (search_design.hpp's as_well_margin; effect_search.cpp, swap_for_better).
  bool shape = false;
  /// Physical bound (empty: none): given the entry's estimate and standard errors in the
  /// selected model (one per param), "" where they are physically possible, else why not (e.g.
  /// "a lever arm of 299 m on a hull 40 m long"). An entry whose estimate breaks its bound is
  /// refused as an explanation: the selection is repeated without it (SearchResult::refused).
  std::function<std::string(const std::vector<double>& estimate, const std::vector<double>& se)> bound{};
  bool scanned() const { return !scan.empty(); }
  bool is_shape() const { return shape || scanned(); }
  std::size_t variants() const { return scan.empty() ? 1 : scan.size(); }
};

/// Which explanation does the data support? Each alternative is a set of catalogue entries
/// (indices into Problem::catalogue) fitted together (grid point 0 of scanned entries).
struct ScopeQuestion {
  std::string question;
  std::vector<std::pair<std::string, std::vector<std::size_t>>> alternatives;  ///< (label, entries)
};

struct Problem {
  std::vector<Channel> channels;
  std::vector<int> channel;        ///< per observation: index into channels
  std::vector<double> t_s;         ///< per observation: time [s]; per channel non-decreasing
  std::vector<double> y;           ///< per observation: residual [channel unit]
  std::vector<char> estimation;    ///< per observation: 1 = estimation window, 0 = scored (held out)
  /// Per observation (empty: 1 everywhere): the gain with which its channel's nominal correlated
  /// component is seen, RMS 1 over each channel's observations, >= 0 (e.g. a position error
  /// seen as an angle: proportional to 1 / range).
  std::vector<double> nominal_corr_gain;
  Eigen::MatrixXd nuisance;        ///< n_obs x q nominal-model parameters (may have 0 columns)
  std::vector<std::string> nuisance_names;
  std::vector<Candidate> catalogue;
  std::vector<std::pair<std::string, std::vector<double>>> covariates;  ///< for "unexplained"
  std::vector<ScopeQuestion> scope_questions;
  std::size_t size() const { return y.size(); }
};

// Limits measured by injection: injected_limits.hpp says how.
struct InjectionOptions {
  int injections = 0;           ///< injections in each check batch at a fitted size (fewer once its verdict is settled), >= 0 (0: Fisher limits only)
  int ladder_injections = 10;   ///< injections per ladder size (fewer once its verdict is settled), >= 1
  int max_ladder = 6;           ///< most ladder sizes per parameter, >= 2
  double max_multiple = 32;     ///< [-] largest multiple of the Fisher limit tried, > 1; beyond it: not reached
  std::uint64_t seed = 1;       ///< seed of the injections' noise streams
  int threads = 2;              ///< concurrent searches, >= 1
  double conf = 0.95;           ///< confidence of the Clopper-Pearson intervals, (0, 1)
  /// Entries measured: "name" (all scopes), "name@scope" or either with ":param"; empty: all.
  std::vector<std::string> entries;
  /// Called with one line per parameter measured (e.g. to show progress on stderr); may be empty.
  std::function<void(const std::string&)> progress;
};

/// One limit found by injection.
struct InjectedSize {
  double size = 0;     ///< [parameter unit] the fitted size hit with probability `power`; infinite: not reached
  int n = 0, hits = 0; ///< the check batch at `size`: injections and hits
  double lo = 0, hi = 1;  ///< its Clopper-Pearson interval for the hit rate
};

struct InjectedLimit {
  double fisher = 0;           ///< [parameter unit] the Fisher-information limit the ladder starts from
  double variant_value = 0;    ///< scanned entries: the grid value injected (e.g. the step time [s])
  InjectedSize named, detected;
  struct Rung {
    double size = 0;
    int n = 0, named = 0, detected = 0;
  };
  std::vector<Rung> ladder;    ///< every ladder size tried, in the order tried
};

/// "name@scope" -> param -> limit, for the entries InjectionOptions::entries selects.
using InjectedLimits = std::map<std::string, std::map<std::string, InjectedLimit>>;

struct SearchOptions {
  double alpha = 0.01;          ///< familywise false-alarm level, (0, 0.5)
  double power = 0.9;           ///< detection probability of the reported detection limits, (0.5, 1)
  double confound_corr = 0.9;   ///< canonical correlation above which two effects are confounded, (0, 1)
  int max_effects = 8;          ///< most effects named, >= 1
  int max_rounds = 3;           ///< noise/effect re-identification rounds, >= 1
  NoiseIdOptions noise;         ///< noise identification (alpha_correlated is set from alpha)
  /// The noise parameters' uncertainty in the test: a selected effect stays only while its
  /// 2 log LR, minimised over each touched channel's noise confidence set (noise_id.hpp's
  /// noise_confidence_set: REML within noise_set_q / 2 of the best), still passes; 0: the
  /// plug-in tests alone. >= 0. The default 4 (about an 86 % set for the two noise parameters)
  /// is chosen by measurement (README: false alarms under tau = 30 s noise and the power table).
  double noise_set_q = 4;
  /// A scanned entry's test (a step, a period, a manoeuvre): the likelihood ratio with the noise
  /// maximised under both hypotheses, the null's only over the noise models the data allow once
  /// the entry is in the model (each touched channel's REML confidence set at null_set_q, the
  /// entry's columns among the fixed effects). Over the whole noise family (0: the profile LR) a
  /// slow correlation that exists only to absorb the step makes the null fit nearly as well: a
  /// glide step of 0.8 sigma at mid-flight was named in 9 of 30 independent flights; with 9
  /// (the 99 % set for two parameters) in 18 of 30, and 3 of 200 paper flights under tau = 30 s
  /// cascade noise named a mean effect either way (4: 23 of 30, but 7 of 200). With the
  /// candidates ranked on one footing (forward selection, effect_search.cpp): 38 of 50 with 9,
  /// 40 of 50 with 4. With a rival that explains the residual better swapped in
  /// (swap_for_better): 43 of 50 with 9, 45 with 6, 47 with 5 and with 4; nominal flights under
  /// tau = 3-30 s noise from the same generator (200 per geometry) named a mean effect in 2, 4
  /// and 3 (intercept, level, turns) with 5, 2, 5 and 3 with 4. >= 0.
  double null_set_q = 5;
  /// Of two entries that explain the same residual, the one forward selection chose gives way
  /// to the other when that is better on the joint likelihood by more than its extra
  /// parameters cost (a shape for a physical cause by more than explaining as well);
  /// effect_search.cpp's swap_for_better says how. false: forward selection's choice stands.
  bool swap_rivals = true;
  /// The Bonferroni family's size when this problem is one part of a larger family searched in
  /// parts (e.g. one target's track of many, target_model.cpp): alpha is split over this many
  /// tests instead of this problem's own (its catalogue entries and three noise tests per
  /// channel); 0: this problem's own. When set, at least this problem's own count.
  double family_size = 0;
  /// Score the held-out frames: the named effects refitted on the estimation frames alone
  /// (those the window does not determine left out, holdout_min_z) predict the rest.
  bool score_holdout = true;
  /// Report the named effects alone (estimates, evidence, confounded_with): no detection limits,
  /// noise findings, outliers, unexplained covariates, scope answers or injected limits (left
  /// empty). What an injected search reads (injected_limits.hpp): the effects do not depend on
  /// the rest.
  bool effects_only = false;
  /// An effect is left out of the held-out prediction (the window does not determine it) when,
  /// fitted on the estimation frames, its largest |estimate / SE| is below this, or its
  /// predicted contribution on the held-out frames is below this many of that prediction's own
  /// SEs (RMS over those frames; the same as |estimate / SE| for a one-parameter effect, smaller
  /// for a multi-parameter one whose held-out part the window leaves open), >= 0.
  double holdout_min_z = 2;
  /// Detection and naming limits measured by injection into the data's own fitted model and
  /// noise (injected_limits.hpp); injection.injections = 0 gives the Fisher limits alone.
  InjectionOptions injection;
  /// Forward selection's candidates tested this many at once, in rank order (the first that
  /// passes enters: the same choice, and the same report, as one at a time), >= 1. The
  /// searches a search runs inside it (injections) test one at a time.
  int threads = 1;
  /// Called at each stage of the search (each round's noise identification, each candidate
  /// tested, the checks, the report) with a line saying where it is, e.g. to show progress on
  /// stderr on a large input; may be empty. May be called from several threads at once (the
  /// diagnoses run searches in parallel); the searches run inside one (injections) do not call it.
  std::function<void(const std::string&)> progress;
  /// Noise fits remembered across searches of the same data (make_noise_memo): a pooled
  /// diagnosis, its carried fit and its leave-one-out share one, so a channel whose frames,
  /// fixed-effect columns, outlier flags and options are the same as in another search is not
  /// identified again. A fit is a function of exactly those (search_detail::NoiseMemo), so the
  /// results are the same with or without it, bit for bit. Empty (the default): the search
  /// remembers its own fits only. Not for searches of different data (the injections do not
  /// pass it on): it would only grow.
  std::shared_ptr<search_detail::NoiseMemo> noise_memo;
};

/// A memo of noise fits for SearchOptions::noise_memo, safe to share between threads.
std::shared_ptr<search_detail::NoiseMemo> make_noise_memo();

/// The replication check of an entry with replicates (replication.hpp).
struct Replication {
  bool tested = false;                   ///< two or more replicates carried data
  std::vector<std::string> recordings;   ///< each replicate's Scope::recording
  std::vector<std::vector<double>> estimate, stderr_;  ///< per replicate, per parameter (GLS, with the rest of the model)
  std::vector<double> mean, mean_se;     ///< per parameter: random-effects mean and its Hartung-Knapp SE
  std::vector<double> between_sd;        ///< per parameter: DerSimonian-Laird between-replicate sd
  double log10_p = 0;                    ///< two-sided t(R - 1) p of the mean, Bonferroni over the parameters
  /// Cochran's Q of the replicates' values about their fixed-effect mean, chi^2(R - 1): log10 of
  /// its p, Bonferroni over the parameters (small: they do not agree with one value)
  double homogeneity_log10_p = 0;
  std::string over = "recordings";       ///< what the replicates are: "recordings" or "targets"
};

struct FoundEffect {
  std::string name;
  Scope scope;
  std::vector<std::string> params;
  std::vector<double> estimate, stderr_;
  std::string scan_param;
  double scan_value = 0, scan_se = 0;  ///< scanned entries: the chosen grid value and its SE
  double lr = 0;                       ///< 2 log LR of the final model against it without this effect (GLS under the final noise)
  double log10_p = 0;                  ///< log10 of its Bonferroni-adjusted p-value
  /// The 2 log LR the selection kept it with, given all the other effects: its plug-in test (a
  /// non-scanned entry under the noise re-identified with it, a scanned one by the profile LR)
  /// and, with noise_set_q > 0, the least over the noise confidence sets; and its adjusted p.
  double kept_lr = 0, kept_log10_p = 0;
  double delta_bic = 0;                ///< BIC(without) - BIC(with)
  struct Confound {
    std::string name;
    Scope scope;
    double corr = 0;   ///< canonical correlation given the rest of the model
    double dlr = 0;    ///< 2 log LR of this effect minus that of the other in its place
    std::size_t entry = 0;  ///< the other's catalogue entry (name and scope do not tell per-channel entries apart)
    std::vector<std::string> params;  ///< its parameters (e.g. which channel's drift)
  };
  std::vector<Confound> confounded_with;
  std::string note;
  std::size_t entry = 0, variant = 0;  ///< catalogue entry and grid point
  Replication replication;             ///< entries with replicates: do they agree?
};

struct ChannelNoise {
  NoiseFit fit;                 ///< identified on the final model's residuals (all frames)
  /// The noise a simulation of this channel draws: identified by maximum likelihood on the
  /// residuals with the final model's fit subtracted, no trend added and correlation times up to
  /// four times the series' span, where a correlated part beats the nominal noise by
  /// use_correlated_lr (else fit) (fit keeps a quadratic trend and tau <= span / 4 so that a slow mean
  /// effect is not taken for noise; what no named effect explains is error all the same, and a
  /// simulation without it is too quiet). Its outlier flags are fit's. `drawn_ok` is false where
  /// the series allowed no such fit (drawn = fit then).
  NoiseFit drawn;
  bool drawn_ok = false;
  /// The channel's offset group (Channel::offset_group) when its offset is drawn from the
  /// group's random effect (SearchResult::offsets; drawn is then identified about the
  /// channel's own mean); "" otherwise.
  std::string offset_group;
  /// drawn has a correlated part slower than fit may hold (tau > span / tau_span_divisor) that
  /// raises its sigma over fit's by more than 10 %: a slow wander no named effect explains.
  bool slow_wander = false;
  double noise_scale = 1, noise_scale_se = 0;  ///< fitted sigma / nominal sigma
  double log10_p_scale = 0;     ///< adjusted p of noise_scale != 1
  bool scale_named = false, correlated_named = false, outliers_named = false;
  double outlier_gain = 0;      ///< out-of-sample log-likelihood gain of the outlier mixture
  int outliers_in_runs = 0;     ///< flagged frames with a flagged neighbour (runs: coloured noise, not gross errors)
  /// flagged frames beyond the threshold under every noise model within noise_set_q / 2 of the
  /// best (what the outlier count test counts; the flagged count when no set was needed)
  int outliers_beyond_set = 0;
};

/// The constant offsets no named effect explains on the channels of one offset group (a sensor's
/// quantity on many targets), as a random effect: channel i's residual mean under the final
/// model, m_i (GLS under its drawn noise, identified about that mean) with variance v_i, is
///   m_i = mu + u_i + e_i,  u_i ~ N(0, tau^2),  e_i ~ N(0, v_i),
/// mu and tau^2 by DerSimonian and Laird. A simulation draws one u per target. Channels whose
/// offset a named effect of their own target explains (a non-shape entry that touches some but
/// not all of the group's channels) are left out of it and listed.
struct OffsetGroup {
  std::string group, unit;
  int targets = 0;                    ///< channels in the random effect (>= kMinOffsetTargets)
  double mean = 0, mean_se = 0;       ///< [unit] mu and its SE
  double sd = 0;                      ///< [unit] tau, >= 0
  double q = 0;                       ///< Cochran's Q of the m_i (targets - 1 dof under tau = 0)
  std::vector<std::string> channels;  ///< in the random effect
  std::vector<std::string> explained; ///< left out: a named effect of their own explains their offset
};
inline constexpr int kMinOffsetTargets = 5;  ///< fewer targets: no spread across them to estimate

struct SeriesGain {
  int n = 0;                                       ///< scored frames
  double nominal_rms = 0, extended_rms = 0;        ///< [unit] held-out residual RMS
  double nominal_loglik = 0, extended_loglik = 0;  ///< held-out predictive log-likelihood
};

struct ScopeAnswer {
  std::string question;
  struct Alt {
    std::string label;
    int k = 0;           ///< parameters
    double lr = 0;       ///< 2 log LR against none of them (given the rest of the model)
    double bic = 0;      ///< k log n - lr (smaller is better)
  };
  std::vector<Alt> alternatives;
  std::string supported;  ///< label with the smallest BIC ("none" if none beats it)
};

struct SeparationLimit {
  double size = 0;        ///< [the parameter's unit], > 0, may be infinite
  std::string partner;    ///< the entry it must be told from
  double rho = 0;         ///< [-] |partial correlation| with the partner given the nuisance, [0, 1]
  /// [the parameter's unit], > 0, may be infinite: the naming limit, 2 z_power SE(entry |
  /// nuisance, partner). Below it no rule that names at most one of the two (however chosen,
  /// knowing the noise) names both this entry hidden at that size and the partner hidden at the
  /// size that mimics it (its least-squares fit to the same signal), each with the reported
  /// power: the two are simple hypotheses d = size / SE(entry | nuisance, partner) standard
  /// deviations apart, and the best rule's smaller hit rate is Phi(d / 2) (Neyman-Pearson).
  /// A rule that must also keep naming the absent one below alpha needs (z_alpha + z_power) SE,
  /// about the separation limit.
  double naming_size = 0;
};

/// An entry the selection took whose estimate broke its physical bound (Candidate::bound).
struct RefusedEffect {
  std::size_t entry = 0;
  std::string name;
  Scope scope;
  std::vector<std::string> params;
  std::vector<double> estimate, stderr_;  ///< in the model it was selected into
  std::string reason;                     ///< the bound's words
};

struct SearchResult {
  std::vector<FoundEffect> effects;
  std::vector<RefusedEffect> refused;           ///< refused as explanations (physical bounds), in the order found
  std::vector<ChannelNoise> noise;              ///< per channel
  std::vector<OffsetGroup> offsets;             ///< per offset group with kMinOffsetTargets channels
  Eigen::VectorXd nuisance_fit, effect_fit;     ///< per observation, full-data fit (the extended model's two parts)
  Eigen::VectorXd nominal_fit;                  ///< per observation, the nominal model (nuisance alone) fitted to all data
  Eigen::VectorXd nuisance_beta, nuisance_se;  ///< the nuisance's estimate and SE (full data)
  Eigen::VectorXd nominal_oos, extended_oos;    ///< per observation: fitted on the estimation frames only
  /// The held-out fits' coefficients: nominal = the nuisance's; extended = the nuisance's, then
  /// each kept effect's columns in the order of holdout_entries.
  Eigen::VectorXd nominal_oos_beta, extended_oos_beta;
  Eigen::VectorXd extended_oos_se;  ///< the extended held-out fit's standard errors (scale from its whitened residuals)
  std::vector<std::pair<std::size_t, std::size_t>> holdout_entries;  ///< (catalogue entry, grid point) kept
  std::vector<std::string> holdout_effects;     ///< the named effects the estimation frames determine ("name@scope")
  std::vector<SeriesGain> gain;                ///< per channel
  std::map<std::string, std::map<std::string, double>> detection_limits;  ///< "name@scope" -> param -> size
  /// "name@scope" -> param -> the size detected with the same probability given the other
  /// non-scanned entry that makes it hardest (the size that tells the two apart), and that entry
  /// ("name (scope; params)"; "" when none is harder than alone). Infinite when no size can.
  std::map<std::string, std::map<std::string, SeparationLimit>> separation_limits;
  /// The limits measured by injection (empty when SearchOptions::injection.injections is 0).
  InjectedLimits injected;
  std::vector<std::string> unexplained;
  std::vector<ScopeAnswer> scopes;
  double family_size = 0;                       ///< m of the Bonferroni split
  std::string familywise;                       ///< the stated rule, for reports
};

/// Run the search. Throws std::invalid_argument naming the culprit on an inconsistent problem
/// (sizes, non-finite values, times out of order, a column function of the wrong shape).
SearchResult search_effects(const Problem& pb, const SearchOptions& o);

}  // namespace rnav
