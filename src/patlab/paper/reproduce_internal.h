// Inside `patlab reproduce` (reproduce.h): the paper's numbers, checked against the tables the
// reproduction regenerated (reproduce_claims.cpp).
#pragma once

#include <string>
#include <vector>

#include "patlab/analysis/track.h"
#include "patlab/paper/reproduce.h"
#include "patlab/sim/experiment.h"

namespace patlab::paper {

// The regenerated CSVs the paper's numbers are read from.
struct RegeneratedTables {
  std::string fig5_csv, table1_csv, tests_csv;  // fig5.csv, table1.csv, table1_tests.csv
};

// Appends every number of the paper that patlab checks or reports (Tables I and II, section II's
// set-up and claims, Fig. 5 and section IV), each judged by its rule.
void AddPaperNumbers(const ReproduceOptions& options, const sim::Experiment& fig5,
                     const analysis::TrackOptions& table1, const RegeneratedTables& tables,
                     std::vector<PaperNumber>* out);

}  // namespace patlab::paper
