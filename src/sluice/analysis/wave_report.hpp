// What `sluice analyze` prints and writes for a WaveAnalysis: a table, CSVs, SVG plots and an HTML page.
#pragma once

#include <filesystem>
#include <string>

#include "sluice/analysis/waves.hpp"
#include "sluice/case/case.hpp"

namespace sluice::analysis {

// The table printed on the terminal.
std::string wave_table(const WaveAnalysis& w, const Case& c, const std::filesystem::path& run_dir);

// Writes into out_dir: waves.csv (the time series), summary.csv (quantity,value,unit), crest.svg
// (crest and front positions), crest_height.svg, sloshing.svg (centre of mass) and report.html.
void write_wave_report(const WaveAnalysis& w, const Case& c, const std::filesystem::path& run_dir,
                       const std::filesystem::path& out_dir);

}  // namespace sluice::analysis
