// Probes and gauges declared in the case, sampled during the run:
//   pressure: the pressure interpolated with the run's kernel (Shepard-normalised, or first-order
//             corrected) from the fluid particles around a point (and the wall particles, with Adami
//             walls), or its mean over a sensor of finite size on the nearest wall surface;
//   gauge:    water height on a vertical line: top of the highest fluid particle (up + dx/2) within a
//             band around the line;
//   front:    furthest fluid particle from a point along a direction (its distance, and its position).
// Pressure probes and gauges look only at the cells around them (the cell grid); the front is a
// maximum over all the fluid, one multiply-add per particle.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "sluice/case/case.hpp"
#include "sluice/io/append_file.hpp"
#include "sluice/simulation.hpp"

namespace sluice {

// One sample of a probe: the values after the time column.
std::vector<double> sample_probe(const Probe& probe, const Simulation& sim);
std::string probe_header(const Probe& probe, int dimension);

class ProbeRecorder {
 public:
  // Rows already on disk after `keep_until` are dropped (a restart continues from there). With several
  // processes, every process samples (the samples are sums over all of them) and only the root
  // process, `writes`, keeps the rows and touches the files.
  ProbeRecorder(const std::vector<Probe>& probes, int dimension, const std::filesystem::path& dir,
                double keep_until, bool fresh, bool writes = true);
  void sample(const Simulation& sim);  // called after every step; honours each probe's interval
  void flush();                        // appends the rows sampled since the last flush to each CSV
  void sync();                         // makes the flushed rows durable

 private:
  struct Series {
    Probe probe;
    AppendFile file;
    std::string rows;  // sampled since the last flush
    std::int64_t next_sample = 0;
  };
  std::vector<Series> series_;
  bool writes_ = true;
};

// Keeps the header and the rows whose first column is <= t_max, whole lines only (a last line without
// its newline was cut off); used to continue CSVs on restart. The result is a prefix of `csv`.
std::string csv_rows_until(const std::string& csv, double t_max);

}  // namespace sluice
