// The CSV reader (common/csv_table): numbers, empty cells, text and optional columns.
#include "common/io/csv_table.hpp"
#include "test/fuzz/fuzz_target.hpp"

void rnav::fuzz::run_one(const std::uint8_t* data, std::size_t size) {
  const std::string f = write_scratch("table.csv", data, size);
  rnav::CsvTable::read_columns(f, {{"t_s", rnav::CsvKind::kNumber, false},
                                   {"sensor", rnav::CsvKind::kText, false},
                                   {"range_m", rnav::CsvKind::kNumberOrEmpty, false},
                                   {"elevation_deg", rnav::CsvKind::kNumber, true}});
}
