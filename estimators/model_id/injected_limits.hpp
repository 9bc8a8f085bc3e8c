// Detection and naming limits measured by injection (parametric bootstrap), not promised by
// the Fisher information.
//
// A limit is what the whole decision rule achieves: noise identification, the noise confidence
// set, forward selection and the backward checks. For each catalogue entry and parameter the
// data's own fitted model (nuisance and the named effects, without the entry itself) is kept,
// its identified noise is drawn afresh per channel (noise_model.hpp's sample_noise), the entry's
// own columns - exactly what the diagnosis fits - are added at size a, and search_effects runs on
// the result. An injection is
//   named     when the entry itself is among the named effects;
//   detected  when it is named, or a named effect lists it under confounded_with (the report
//             says the data cannot tell the two apart).
// The size is found on a ladder that starts at the Fisher limit: the rates are fitted by a probit
// in log a (P(hit | a) = Phi(b0 + b1 log a), penalised maximum likelihood, b1 >= 0.5 with a weak
// prior). Until the named rate reaches `power` the ladder goes up, until the detected rate falls
// below it down: the first step to where the probit crosses `power` (1.25 to 2 times beyond the
// sizes tried), each further one a doubling (halving); then one more rung goes where the fitted
// curve crosses unless a rung lies within 12 % of it. The fitted size is then checked by a fresh batch of injections at it; a
// batch whose Clopper-Pearson interval excludes `power` joins the ladder and the size is
// refitted and checked again (at most three batches). Every batch stops as soon as its verdict
// is settled (a rung's "rate >= power", a check's "interval contains power" over its full
// size): the same verdict from fewer searches. The report gives the last check's count and
// interval, so the stated limit carries its own evidence.
// Scanned entries are injected at their grid's middle point (a step at mid-span).
// The parameters are measured at once, one per thread (with fewer parameters than threads, a
// parameter's injections share the threads). Deterministic: injection i of (entry, parameter,
// stage) draws from its own seeded stream, whatever the number of threads.
#pragma once

#include "estimators/model_id/effect_search.hpp"

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace rnav {

/// What one injection gave: the entry named, or detected (named, or a named effect confounded with it).
struct InjectionHit {
  bool named = false, detected = false;
};
/// One injection at size a [parameter unit]: injection i (from 0) of batch batch_id (the batches
/// of one ladder numbered from 0 in the order run). Must depend on (a, batch_id, i) alone, and be
/// safe to call from several threads at once.
using InjectionDraw = std::function<InjectionHit(double a, std::size_t batch_id, int i)>;

/// The ladder, fitted sizes and check batches of one parameter (above), its injections drawn by
/// `draw`: measure_injected_limits runs it with draw = a whole search on bootstrapped data; a
/// study of the ladder itself may give a known hit curve. fisher: the ladder's first size, finite
/// and > 0; power: the rate the limits are stated at, (0, 1); io: the batch sizes, conf, and
/// io.threads injections at a time (io.injections >= 1). variant_value is left 0.
/// Throws std::invalid_argument on bad input.
InjectedLimit measure_ladder(const InjectionDraw& draw, double fisher, double power, const InjectionOptions& io);

/// Measure the limits of the problem `pb` whose search gave `res` under options `o`
/// (o.injection is ignored inside: the injected searches measure no limits themselves).
/// Throws std::invalid_argument on bad options or an unknown entry in io.entries.
InjectedLimits measure_injected_limits(const Problem& pb, const SearchResult& res, const SearchOptions& o,
                                       const InjectionOptions& io);

/// The first name in io.entries that selects no catalogue entry of pb ("" when all do): adapters
/// check it before the search, to refuse a misspelt entry at once as bad input.
std::string unknown_injection_entry(const Problem& pb, const InjectionOptions& io);

/// True when entry e, parameter j, is selected by the list (empty: all).
bool injection_selects(const std::vector<std::string>& entries, const Candidate& c, const std::string& param);

}  // namespace rnav
