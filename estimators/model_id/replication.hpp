// The replication check of an entry that claims one value wherever it applies (hardware: a
// sensor's clock in every recording) while the data come in replicates (recordings), each with
// slow noise and effects of its own that the model does not know. Pooled, tens of thousands of
// frames make any compromise value significant; what says the value is one is that the
// replicates agree. Each replicate's value is fitted (its scope_only copy, Candidate::replicates,
// with the rest of the model, GLS under the identified noise), and the random-effects mean over
// the replicates is tested against the spread between them (Hartung-Knapp-Sidik-Jonkman: the
// mean's SE from the weighted spread of the replicates about it, t with R - 1 degrees of freedom,
// R the replicates with data; DerSimonian-Laird between-replicate variance in the weights).
#pragma once

#include "estimators/model_id/entry_tests.hpp"
#include "estimators/model_id/search_design.hpp"

namespace rnav::search_detail {

/// Chosen entry s's replicates (its Candidate::replicates at its grid point) fitted jointly with
/// the other chosen entries; `tested` false when fewer than two replicates carry data.
Replication replication(const Design& d, const Chosen& chosen, std::size_t s);

/// Two-sided tail of Student's t with nu > 0 degrees of freedom: P(|T| > t).
double t_two_sided(double t, double nu);

}  // namespace rnav::search_detail
