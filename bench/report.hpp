// What `clraster bench` prints: a table, a row as each scene finishes, or one JSON object.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "bench/runner.hpp"

namespace clraster::bench {

// The title and column heads.
void print_table_head(std::ostream& out, const RunOptions& options);
// A scene's row: its times, or, when its pictures disagree, how far they do. Returns `out`.
std::ostream& print_table_row(std::ostream& out, const SceneResult& result);
// The geometric mean of the ratios, the devices, and what the columns measure.
void print_table_foot(std::ostream& out, const std::vector<SceneResult>& results);

// Everything as one JSON object: the run's options, each scene's numbers (those of the table, the
// frames' times and the comparison of the pictures) and the geometric mean (null when no scene
// passed).
std::string to_json(const RunOptions& options, const std::vector<SceneResult>& results);

}  // namespace clraster::bench
