#include "estimators/model_id/search_json.hpp"

#include "estimators/model_id/shown_unit.hpp"
#include "estimators/model_id/stats.hpp"

#include <cmath>
#include <sstream>

namespace rnav {

nlohmann::ordered_json scope_json(const Scope& s) {
  nlohmann::ordered_json j;
  j["sensor"] = s.sensor.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(s.sensor);
  j["target"] = s.target.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(s.target);
  if (!s.recording.empty()) j["recording"] = s.recording;
  return j;
}

namespace {
nlohmann::ordered_json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(); }

nlohmann::ordered_json one_or_list(const std::vector<double>& v) {
  return v.size() == 1 ? nlohmann::ordered_json(v[0]) : nlohmann::ordered_json(v);
}
Scope channel_scope(const Channel& c) { return {c.sensor, c.target}; }
}  // namespace

nlohmann::ordered_json evidence_json(const FoundEffect& e) {
  return {{"lr", e.lr}, {"log10_p_adjusted", e.log10_p}, {"kept_lr", e.kept_lr}, {"kept_log10_p_adjusted", e.kept_log10_p},
          {"delta_bic", e.delta_bic}};
}

nlohmann::ordered_json search_json(const Problem& pb, const SearchResult& r) {
  nlohmann::ordered_json j;
  j["effects"] = nlohmann::ordered_json::array();
  for (const auto& e : r.effects) {
    nlohmann::ordered_json x;
    x["name"] = e.name;
    x["scope"] = scope_json(e.scope);
    x["params"] = e.params;
    x["estimate"] = one_or_list(e.estimate);
    x["stderr"] = one_or_list(e.stderr_);
    if (!e.scan_param.empty()) x["scanned"] = {{"param", e.scan_param}, {"value", e.scan_value}, {"stderr", e.scan_se}};
    x["evidence"] = evidence_json(e);
    if (e.replication.tested) {
      const Replication& r = e.replication;
      x["replication"] = {{"recordings", r.recordings}, {"estimate", r.estimate}, {"stderr", r.stderr_}, {"mean", r.mean},
                          {"mean_se", r.mean_se}, {"between_sd", r.between_sd}, {"log10_p", r.log10_p}};
    }
    x["confounded_with"] = nlohmann::ordered_json::array();
    for (const auto& c : e.confounded_with)
      x["confounded_with"].push_back({{"name", c.name}, {"scope", scope_json(c.scope)}, {"params", c.params}, {"canonical_corr", c.corr},
                                      {"lr_difference", c.dlr}});
    if (!e.note.empty()) x["note"] = e.note;
    j["effects"].push_back(x);
  }
  // noise findings as effects too (scope = the channel's)
  for (std::size_t c = 0; c < r.noise.size(); ++c) {
    const auto& n = r.noise[c];
    const Channel& ch = pb.channels[c];
    if (n.scale_named)
      j["effects"].push_back({{"name", "noise_scale"}, {"scope", scope_json(channel_scope(ch))}, {"channel", ch.name},
                              {"params", {"ratio"}}, {"estimate", n.noise_scale}, {"stderr", n.noise_scale_se},
                              {"evidence", {{"log10_p_adjusted", n.log10_p_scale}}},
                              {"note", "fitted sigma " + short_num(std::sqrt(n.fit.params.s2)) + " " + ch.unit +
                                           " against the nominal " + short_num(ch.nominal_sigma) + " " + ch.unit}});
    if (n.correlated_named)
      j["effects"].push_back({{"name", "correlated_noise"}, {"scope", scope_json(channel_scope(ch))}, {"channel", ch.name},
                              {"params", {"tau_s", "correlated_share"}}, {"estimate", {n.fit.params.tau_s, n.fit.params.lambda}},
                              {"stderr", {n.fit.se_tau_s, nullptr}},
                              {"evidence", {{"lr", 2 * (n.fit.loglik_correlated - n.fit.loglik_white)}}},
                              {"note", n.fit.params.kind() + " noise; every mean effect is tested under it"}});
    if (n.outliers_named)
      j["effects"].push_back({{"name", "outliers"}, {"scope", scope_json(channel_scope(ch))}, {"channel", ch.name},
                              {"params", {"fraction"}}, {"estimate", n.fit.params.p_out},
                              {"stderr", std::sqrt(n.fit.params.p_out * (1 - n.fit.params.p_out) / std::max(1, n.fit.n))},
                              {"evidence", {{"heldout_loglik_gain", n.outlier_gain}}},
                              {"note", "frames beyond " + short_num(n.fit.z_outlier) +
                                           " sigma of their prediction; the mixture raises the held-out likelihood"}});
  }
  j["noise"] = nlohmann::ordered_json::object();
  for (std::size_t c = 0; c < r.noise.size(); ++c) {
    const auto& n = r.noise[c];
    j["noise"][pb.channels[c].name] = {{"model", n.fit.params.kind()},
                                       {"sigma", std::sqrt(n.fit.params.s2)},
                                       {"unit", pb.channels[c].unit},
                                       {"tau_s", n.fit.correlated ? nlohmann::ordered_json(n.fit.params.tau_s) : nlohmann::ordered_json(nullptr)},
                                       {"correlated_share", n.fit.params.lambda},
                                       {"outlier_fraction", n.fit.params.p_out},
                                       {"outlier_frames", static_cast<int>(n.fit.outlier.size()) - n.fit.n},
                                       {"outlier_frames_in_runs", n.outliers_in_runs},
                                       {"outlier_frames_beyond_noise_set", n.outliers_beyond_set},
                                       {"noise_scale", n.noise_scale},
                                       {"frames", n.fit.n},
                                       // what a simulation needs to draw the same noise (common/physics/noise_process.hpp)
                                       {"outlier_sd", std::sqrt(n.fit.params.s_out2)},
                                       {"nominal_share", n.fit.params.nom_share}};
    // what a simulation of the channel draws (ChannelNoise::drawn): the identified noise with the
    // slow wander no named effect explains (none above when slow_wander is false)
    if (n.drawn_ok)
      j["noise"][pb.channels[c].name]["simulated"] = {
          {"model", n.drawn.params.kind()},
          {"sigma", std::sqrt(n.drawn.params.s2)},
          {"tau_s", n.drawn.correlated ? nlohmann::ordered_json(n.drawn.params.tau_s) : nlohmann::ordered_json(nullptr)},
          {"correlated_share", n.drawn.params.lambda},
          {"slow_wander", n.slow_wander},
          // where set, the channel's offset is drawn from this group of "offsets" and the noise
          // above is identified about the channel's own mean
          {"offset_group", n.offset_group.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(n.offset_group)}};
    // the nominal model's own correlated component (Channel::nominal_corr_sigma: a nav error, a
    // reference's interpolation), where the channel has one
    if (pb.channels[c].nominal_corr_sigma > 0) {
      j["noise"][pb.channels[c].name]["nominal_correlated_sigma"] = pb.channels[c].nominal_corr_sigma;
      j["noise"][pb.channels[c].name]["nominal_correlated_tau_s"] = pb.channels[c].nominal_corr_tau_s;
    }
  }
  // the offsets no named effect explains, a random effect across each group's targets
  // (OffsetGroup), in the channels' units
  j["offsets"] = nlohmann::ordered_json::object();
  for (const auto& g : r.offsets)
    j["offsets"][g.group] = {{"unit", g.unit},        {"mean", g.mean}, {"mean_se", g.mean_se}, {"sd", g.sd},
                             {"targets", g.targets}, {"q", g.q},       {"channels", g.channels}, {"explained", g.explained}};
  j["series_gain"] = nlohmann::ordered_json::object();
  for (std::size_t c = 0; c < r.gain.size(); ++c) {
    const auto& g = r.gain[c];
    j["series_gain"][pb.channels[c].name] = {{"n", g.n}, {"unit", pb.channels[c].unit}, {"nominal_rms", g.nominal_rms},
                                             {"extended_rms", g.extended_rms}, {"nominal_loglik", g.nominal_loglik},
                                             {"extended_loglik", g.extended_loglik}};
  }
  j["gain_fit"] = gain_fit_json(pb, r);
  const nlohmann::ordered_json limits = limits_json(pb, r);
  for (const auto& [k, v] : limits.items()) j[k] = v;
  j["separation_limits"] = separation_json(r);
  j["scope_support"] = nlohmann::ordered_json::array();
  for (const auto& s : r.scopes) {
    nlohmann::ordered_json q;
    q["question"] = s.question;
    q["supported"] = s.supported;
    q["alternatives"] = nlohmann::ordered_json::array();
    for (const auto& a : s.alternatives) q["alternatives"].push_back({{"label", a.label}, {"k", a.k}, {"lr", a.lr}, {"bic", a.bic}});
    j["scope_support"].push_back(q);
  }
  j["unexplained"] = r.unexplained;
  j["refused"] = nlohmann::ordered_json::array();
  for (const auto& x : r.refused)
    j["refused"].push_back({{"name", x.name}, {"scope", scope_json(x.scope)}, {"params", x.params}, {"estimate", x.estimate},
                            {"stderr", x.stderr_}, {"reason", x.reason}});
  j["familywise"] = r.familywise;
  return j;
}

nlohmann::ordered_json limits_json(const Problem& pb, const SearchResult& r,
                                   const std::function<std::string(const std::string&)>& strip) {
  auto key = [&](const std::string& k) { return strip ? strip(k) : k; };
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  out["limits_method"] = r.injected.empty() ? "fisher" : "injection";
  nlohmann::ordered_json det = nlohmann::ordered_json::object(), nam = nlohmann::ordered_json::object(),
                         fis = nlohmann::ordered_json::object(), inj = nlohmann::ordered_json::object();
  for (const auto& [k, m] : r.detection_limits)
    for (const auto& [p, v] : m) fis[key(k)][p] = v, det[key(k)][p] = v;
  auto sized = [](const InjectedSize& s) {
    return nlohmann::ordered_json{{"size", finite_or_null(s.size)}, {"n", s.n}, {"hits", s.hits}, {"cp_lo", s.lo}, {"cp_hi", s.hi}};
  };
  for (const auto& [k, m] : r.injected)
    for (const auto& [p, L] : m) {
      det[key(k)][p] = finite_or_null(L.detected.size);
      nam[key(k)][p] = finite_or_null(L.named.size);
      nlohmann::ordered_json x;
      x["fisher"] = L.fisher;
      for (const Candidate& c : pb.catalogue)
        if (c.scanned() && c.name + "@" + c.scope.label() == k) x["scan_value"] = {{c.scan_param, L.variant_value}};
      x["named"] = sized(L.named);
      x["detected"] = sized(L.detected);
      x["ladder"] = nlohmann::ordered_json::array();
      for (const auto& g : L.ladder) x["ladder"].push_back({g.size, g.n, g.named, g.detected});
      inj[key(k)][p] = x;
    }
  out["detection_limits"] = det;
  out["naming_limits"] = nam;
  out["fisher_limits"] = fis;
  out["injected_limits"] = inj;
  return out;
}

nlohmann::ordered_json separation_json(const SearchResult& r, const std::function<std::string(const std::string&)>& strip) {
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  for (const auto& [k, m] : r.separation_limits)
    for (const auto& [p, s] : m)
      out[strip ? strip(k) : k][p] = {{"size", finite_or_null(s.size)},
                                      {"partner", s.partner},
                                      {"rho", s.rho},
                                      {"naming_size", finite_or_null(s.naming_size)}};
  return out;
}

nlohmann::ordered_json gain_fit_json(const Problem& pb, const SearchResult& r) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  auto col = pb.nuisance.cols();
  for (const auto& [e, v] : r.holdout_entries) {
    const Candidate& c = pb.catalogue[e];
    nlohmann::ordered_json x;
    x["name"] = c.name;
    x["scope"] = scope_json(c.scope);
    x["params"] = c.params;
    std::vector<double> est, se;
    for (std::size_t j = 0; j < c.params.size(); ++j, ++col) {
      est.push_back(r.extended_oos_beta(col));
      se.push_back(r.extended_oos_se(col));
    }
    x["estimate"] = one_or_list(est);
    x["stderr"] = one_or_list(se);
    if (c.scanned()) x["scanned"] = {{"param", c.scan_param}, {"value", c.scan[v]}};
    out.push_back(x);
  }
  return out;
}

std::string gain_fit_text(const Problem& pb, const SearchResult& r) {
  std::ostringstream o;
  auto col = pb.nuisance.cols();
  for (const auto& [e, v] : r.holdout_entries) {
    const Candidate& c = pb.catalogue[e];
    o << " " << c.name << "@" << c.scope.label() << " (";
    for (std::size_t j = 0; j < c.params.size(); ++j, ++col) {
      const ShownUnit u = shown_unit(c.params[j]);
      o << (j ? " " : "") << u.name << "=" << short_num(u.factor * r.extended_oos_beta(col)) << " +- "
        << short_num(u.factor * r.extended_oos_se(col));
    }
    o << ")";
  }
  return o.str();
}

std::string search_text(const Problem& pb, const SearchResult& r) {
  std::ostringstream o;
  for (const auto& e : r.effects) {
    o << "  EFFECT   " << e.name << " [" << e.scope.label() << "]:";
    for (std::size_t i = 0; i < e.estimate.size(); ++i) {
      const ShownUnit u = shown_unit(e.params[i]);
      o << " " << u.name << "=" << short_num(u.factor * e.estimate[i]) << " +- " << short_num(u.factor * e.stderr_[i]);
    }
    if (!e.scan_param.empty()) o << " at " << e.scan_param << "=" << short_num(e.scan_value) << " +- " << short_num(e.scan_se);
    o << "  (2 log LR " << short_num(e.lr) << ", log10 p " << short_num(e.log10_p) << "; kept at " << short_num(e.kept_lr)
      << ", log10 p " << short_num(e.kept_log10_p) << ")";
    for (const auto& c : e.confounded_with) o << "  confounded with " << c.name << " [" << c.scope.label() << "]";
    o << "\n";
    if (e.replication.tested) {
      const Replication& rp = e.replication;
      o << "           replicated in " << rp.recordings.size() << " " << rp.over << ":";
      for (std::size_t i = 0; i < rp.mean.size(); ++i) {
        const ShownUnit u = shown_unit(e.params[i]);
        o << " " << u.name << " mean " << short_num(u.factor * rp.mean[i]) << " +- " << short_num(u.factor * rp.mean_se[i])
          << " (between " << rp.over << " sd " << short_num(u.factor * rp.between_sd[i]) << ")";
      }
      o << ", log10 p " << short_num(rp.log10_p) << "\n";
    }
  }
  for (std::size_t c = 0; c < r.noise.size(); ++c) {
    const auto& n = r.noise[c];
    const ShownUnit u = shown_unit(pb.channels[c].unit);
    o << "  noise    " << pb.channels[c].name << ": " << n.fit.params.kind() << " sigma "
      << short_num(u.factor * std::sqrt(n.fit.params.s2)) << " " << u.name << " (" << short_num(n.noise_scale) << "x nominal" << (n.scale_named ? ", named" : "") << ")";
    if (n.fit.correlated) o << ", tau " << short_num(n.fit.params.tau_s) << " +- " << short_num(n.fit.se_tau_s) << " s";
    if (n.outliers_named) o << ", outliers " << short_num(100 * n.fit.params.p_out) << " %";
    if (n.slow_wander)
      o << "; slow wander no named effect explains: sigma " << short_num(u.factor * std::sqrt(n.drawn.params.s2)) << " " << u.name
        << ", tau " << short_num(n.drawn.params.tau_s) << " s (a simulation draws it)";
    o << "\n";
  }
  for (const auto& g : r.offsets) {
    const ShownUnit u = shown_unit(g.unit);
    o << "  offsets  " << g.group << ": the targets' own offsets no named effect explains, across " << g.targets
      << " targets: mean " << short_num(u.factor * g.mean) << " +- " << short_num(u.factor * g.mean_se) << " " << u.name
      << ", spread (sd) " << short_num(u.factor * g.sd) << " " << u.name << " (Cochran's Q " << short_num(g.q) << " on "
      << g.targets - 1 << " dof); a simulation draws one per target";
    if (!g.explained.empty()) o << " (" << g.explained.size() << " explained by their own effects: not drawn)";
    o << "\n";
  }
  for (const auto& s : r.scopes) o << "  scope    " << s.question << " -> " << s.supported << "\n";
  for (const auto& u : r.unexplained) o << "  unexplained: " << u << "\n";
  for (const auto& x : r.refused) o << "  REFUSED  " << x.name << " [" << x.scope.label() << "]: " << x.reason << "\n";
  return o.str();
}

}  // namespace rnav
