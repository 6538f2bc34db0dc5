// Global reductions: every quantity summed or maximised over all particles (the time step's maxima,
// the diagnostics, the instability guard's count, the probes) goes through a Reducer. A process
// computes its part over the particles it owns and the Reducer combines the parts of all processes:
// one process today (SerialReducer returns its argument), several with MPI.
#pragma once

#include <cstdint>
#include <vector>

namespace sluice {

class Reducer {
 public:
  virtual ~Reducer() = default;
  [[nodiscard]] virtual double sum(double part) const = 0;
  [[nodiscard]] virtual std::int64_t sum(std::int64_t part) const = 0;
  [[nodiscard]] virtual double max(double part) const = 0;
  [[nodiscard]] virtual double min(double part) const = 0;
  // Element-wise sum (in rank order) and maximum of equal-length vectors.
  [[nodiscard]] virtual std::vector<double> sum(std::vector<double> parts) const = 0;
  [[nodiscard]] virtual std::vector<double> max(std::vector<double> parts) const = 0;
  // The payload of the part with the largest value (of equal values, the first process's).
  [[nodiscard]] virtual std::vector<double> payload_of_max(double value, std::vector<double> payload) const = 0;
};

class SerialReducer final : public Reducer {
 public:
  [[nodiscard]] double sum(double part) const override { return part; }
  [[nodiscard]] std::int64_t sum(std::int64_t part) const override { return part; }
  [[nodiscard]] double max(double part) const override { return part; }
  [[nodiscard]] double min(double part) const override { return part; }
  [[nodiscard]] std::vector<double> sum(std::vector<double> parts) const override { return parts; }
  [[nodiscard]] std::vector<double> max(std::vector<double> parts) const override { return parts; }
  [[nodiscard]] std::vector<double> payload_of_max(double, std::vector<double> payload) const override {
    return payload;
  }
};

// The reducer of a single process.
inline const Reducer& serial_reducer() {
  static const SerialReducer reducer;
  return reducer;
}

}  // namespace sluice
