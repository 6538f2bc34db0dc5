#include "sluice/geometry/motion.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <string_view>

namespace sluice {

double ScalarLaw::largest_magnitude(double end) const {
  // Sampled: enough for the set-up check it serves, which keeps a margin of its own.
  constexpr int samples = 4096;
  double largest = 0.0;
  for (int k = 0; k <= samples; ++k) largest = std::max(largest, std::abs(at(end * k / samples).value));
  return largest;
}

LinearLaw::LinearLaw(double rate, double start, double end) : rate_(rate), start_(start), end_(end) {
  if (!(end > start)) throw MotionError(fmt::format("a linear motion's end time {} is not after its start {}", end, start));
}

LawValue LinearLaw::at(double t) const {
  if (t <= start_) return {};
  if (t >= end_) return {rate_ * (end_ - start_), 0.0, 0.0};
  return {rate_ * (t - start_), rate_, 0.0};
}

PolynomialLaw::PolynomialLaw(std::vector<double> coefficients, double start, double end, AfterInterval after)
    : c_(std::move(coefficients)), start_(start), end_(end), after_(after) {
  if (c_.empty()) throw MotionError("a polynomial motion needs at least one coefficient");
  if (!(end > start))
    throw MotionError(fmt::format("a polynomial motion's end time {} is not after its start {}", end, start));
}

// Horner's scheme for the value and its two derivatives at once.
LawValue PolynomialLaw::polynomial(double tau) const {
  double p = 0.0, dp = 0.0, ddp = 0.0;
  for (std::size_t k = c_.size(); k-- > 0;) {
    ddp = ddp * tau + 2.0 * dp;
    dp = dp * tau + p;
    p = p * tau + c_[k];
  }
  return {p, dp, ddp};
}

LawValue PolynomialLaw::at(double t) const {
  if (t < start_) return {c_.front(), 0.0, 0.0};
  if (t <= end_) return polynomial(t - start_);
  const LawValue e = polynomial(end_ - start_);
  if (after_ == AfterInterval::hold) return {e.value, 0.0, 0.0};
  return {e.value + e.rate * (t - end_), e.rate, 0.0};
}

double PolynomialLaw::settled_after() const {
  if (after_ == AfterInterval::hold || polynomial(end_ - start_).rate == 0.0) return end_;
  return std::numeric_limits<double>::infinity();
}

SinusoidalLaw::SinusoidalLaw(double amplitude, double period, double phase, double start, double ramp_periods)
    : amplitude_(amplitude), period_(period), phase_(phase), start_(start), ramp_periods_(ramp_periods) {
  if (!(period > 0.0)) throw MotionError(fmt::format("a sinusoidal motion's period {} is not positive", period));
  if (!(ramp_periods >= 0.0)) throw MotionError(fmt::format("a sinusoidal motion's ramp {} is negative", ramp_periods));
}

LawValue SinusoidalLaw::at(double t) const {
  if (t <= start_) return {};
  const double tau = t - start_, omega = 2.0 * std::numbers::pi / period_;
  const double s = std::sin(omega * tau + phase_), c = std::cos(omega * tau + phase_);
  const double g = amplitude_ * (s - std::sin(phase_)), dg = amplitude_ * omega * c, ddg = -amplitude_ * omega * omega * s;
  double r = 1.0, dr = 0.0, ddr = 0.0;
  const double ramp = ramp_periods_ * period_;
  if (tau < ramp) {
    const double k = std::numbers::pi / ramp;
    r = 0.5 * (1.0 - std::cos(k * tau));
    dr = 0.5 * k * std::sin(k * tau);
    ddr = 0.5 * k * k * std::cos(k * tau);
  }
  return {g * r, dg * r + g * dr, ddg * r + 2.0 * dg * dr + g * ddr};
}

double SinusoidalLaw::largest_magnitude(double /*end*/) const {
  return std::abs(amplitude_) * (1.0 + std::abs(std::sin(phase_)));
}

SineSumLaw::SineSumLaw(std::vector<Term> terms, double start, double ramp_time, double repeat_period)
    : terms_(std::move(terms)), start_(start), ramp_time_(ramp_time), repeat_period_(repeat_period) {
  if (terms_.empty()) throw MotionError("a sum of sinusoids needs at least one term");
  if (!(ramp_time >= 0.0)) throw MotionError(fmt::format("a sum of sinusoids' ramp {} s is negative", ramp_time));
  if (!(repeat_period > 0.0))
    throw MotionError(fmt::format("a sum of sinusoids' repeat period {} s is not positive", repeat_period));
}

LawValue SineSumLaw::at(double t) const {
  if (t <= start_) return {};
  const double tau = t - start_;
  double g = 0.0, dg = 0.0, ddg = 0.0;
  for (const Term& term : terms_) {
    const double angle = term.omega * tau + term.phase;
    const double s = std::sin(angle), c = std::cos(angle);
    g += term.amplitude * s;
    dg += term.amplitude * term.omega * c;
    ddg -= term.amplitude * term.omega * term.omega * s;
  }
  if (!(tau < ramp_time_)) return {g, dg, ddg};
  const double k = std::numbers::pi / ramp_time_;
  const double r = 0.5 * (1.0 - std::cos(k * tau)), dr = 0.5 * k * std::sin(k * tau), ddr = 0.5 * k * k * std::cos(k * tau);
  return {g * r, dg * r + g * dr, ddg * r + 2.0 * dg * dr + g * ddr};
}

TableLaw::TableLaw(std::vector<double> times, std::vector<double> values) : t_(std::move(times)), y_(std::move(values)) {
  const std::size_t n = t_.size();
  if (n < 2 || y_.size() != n) throw MotionError("a motion table needs at least two rows of time and value");
  for (std::size_t i = 1; i < n; ++i)
    if (!(t_[i] > t_[i - 1]))
      throw MotionError(fmt::format("a motion table's times must increase: {} follows {}", t_[i], t_[i - 1]));
  // The natural spline's second derivatives: a tridiagonal system (Thomas algorithm), zero at both ends.
  m_.assign(n, 0.0);
  if (n == 2) return;
  std::vector<double> diag(n, 0.0), rhs(n, 0.0), upper(n, 0.0);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double h0 = t_[i] - t_[i - 1], h1 = t_[i + 1] - t_[i];
    diag[i] = 2.0 * (h0 + h1);
    upper[i] = h1;
    rhs[i] = 6.0 * ((y_[i + 1] - y_[i]) / h1 - (y_[i] - y_[i - 1]) / h0);
    if (i > 1) {
      const double w = h0 / diag[i - 1];
      diag[i] -= w * upper[i - 1];
      rhs[i] -= w * rhs[i - 1];
    }
  }
  for (std::size_t i = n - 1; i-- > 1;) m_[i] = (rhs[i] - upper[i] * m_[i + 1]) / diag[i];
}

LawValue TableLaw::at(double t) const {
  if (t <= t_.front()) return {y_.front(), 0.0, 0.0};
  if (t >= t_.back()) return {y_.back(), 0.0, 0.0};
  const std::size_t i = static_cast<std::size_t>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin()) - 1;
  const double h = t_[i + 1] - t_[i], a = (t_[i + 1] - t) / h, b = (t - t_[i]) / h;
  const double value = a * y_[i] + b * y_[i + 1] + ((a * a * a - a) * m_[i] + (b * b * b - b) * m_[i + 1]) * h * h / 6.0;
  const double rate = (y_[i + 1] - y_[i]) / h - (3.0 * a * a - 1.0) / 6.0 * h * m_[i] + (3.0 * b * b - 1.0) / 6.0 * h * m_[i + 1];
  return {value, rate, a * m_[i] + b * m_[i + 1]};
}

AbsorbingLaw::AbsorbingLaw(std::shared_ptr<const ScalarLaw> target, std::shared_ptr<const ScalarLaw> target_elevation,
                           double gain, double delay, double time_constant, double limit)
    : target_(std::move(target)),
      elevation_(std::move(target_elevation)),
      gain_(gain),
      delay_(delay),
      spacing_(delay / static_cast<double>(history - 2)),
      tau_(time_constant),
      limit_(limit) {
  if (!(gain > 0.0) || !std::isfinite(gain)) throw MotionError(fmt::format("an absorber's gain {} is not positive", gain));
  if (!(delay >= 0.0) || !std::isfinite(delay)) throw MotionError(fmt::format("an absorber's delay {} s is negative", delay));
  if (!(time_constant > 0.0) || !std::isfinite(time_constant))
    throw MotionError(fmt::format("an absorber's time constant {} s is not positive", time_constant));
  if (!(limit > 0.0) || !std::isfinite(limit)) throw MotionError(fmt::format("an absorber's limit {} m is not positive", limit));
}

double AbsorbingLaw::offset_at(double t) const {
  return std::clamp(state_.offset + state_.rate * (t - state_.time), -limit_, limit_);
}

LawValue AbsorbingLaw::at(double t) const {
  LawValue v = target_ ? target_->at(t) : LawValue{};
  const double x = offset_at(t);
  v.value += x;
  // Held at the limit, the correction rests.
  if (std::abs(x) < limit_) v.rate += state_.rate;
  return v;
}

double AbsorbingLaw::largest_magnitude(double end) const {
  return (target_ ? target_->largest_magnitude(end) : 0.0) + limit_;
}

double AbsorbingLaw::target_elevation(double t) const { return elevation_ ? elevation_->at(t).value : 0.0; }

void AbsorbingLaw::observe(double t, double elevation) {
  const double x = offset_at(t);
  const double error = elevation - target_elevation(t);
  State& s = state_;
  const bool first = s.observed == 0.0;
  const double since = first ? 0.0 : t - s.time;
  if (first) {
    // The first observation is the level the run starts from: the correction starts at rest there,
    // and the past is taken to have been the same.
    s.observed = 1.0;
    s.newest = t;
    s.past.fill(error);
  } else if (spacing_ > 0.0) {
    // The past errors on their grid, linear between the last observation and this one.
    while (s.newest + spacing_ <= t) {
      s.newest += spacing_;
      const double w = (s.newest - s.time) / (t - s.time);
      std::copy_backward(s.past.begin(), s.past.end() - 1, s.past.end());
      s.past[0] = s.error + w * (error - s.error);
    }
  }
  s.time = t;
  s.error = error;
  // e at t - delay: newer than the oldest kept sample, older than the newest (t - newest < spacing).
  double delayed = error;
  if (spacing_ > 0.0) {
    const double back = (s.newest - (t - delay_)) / spacing_;
    const auto k = std::min(static_cast<std::size_t>(std::max(0.0, std::floor(back))), history - 2);
    const double f = std::clamp(back - static_cast<double>(k), 0.0, 1.0);
    delayed = s.past[k] + f * (s.past[k + 1] - s.past[k]);
  }
  s.mean_error = first ? delayed : s.mean_error + std::min(1.0, since / tau_) * (delayed - s.mean_error);
  s.offset = x;
  s.rate = -gain_ * (delayed - s.mean_error) - x / tau_;
}

std::array<double, AbsorbingLaw::state_size> AbsorbingLaw::packed() const {
  std::array<double, state_size> v{state_.time,  state_.offset, state_.rate,  state_.mean_error,
                                   state_.observed, state_.error, state_.newest};
  std::copy(state_.past.begin(), state_.past.end(), v.begin() + 7);
  return v;
}

void AbsorbingLaw::unpack(const double* v) {
  state_.time = v[0];
  state_.offset = v[1];
  state_.rate = v[2];
  state_.mean_error = v[3];
  state_.observed = v[4];
  state_.error = v[5];
  state_.newest = v[6];
  std::copy(v + 7, v + state_size, state_.past.begin());
}

double TableLaw::largest_magnitude(double end) const {
  double largest = ScalarLaw::largest_magnitude(end);
  for (const double y : y_) largest = std::max(largest, std::abs(y));
  return largest;
}

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '"')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '"' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> cells;
  for (std::size_t at = 0;;) {
    const std::size_t comma = line.find(',', at);
    cells.push_back(trim(line.substr(at, comma == std::string_view::npos ? std::string_view::npos : comma - at)));
    if (comma == std::string_view::npos) return cells;
    at = comma + 1;
  }
}

}  // namespace

MotionSeries parse_motion_csv(const std::string& text, const std::string& name, const std::string& time_column,
                              const std::string& value_column, double scale, double time_offset) {
  std::istringstream in(text);
  std::string line;
  long number = 0;
  std::vector<std::string_view> header;
  std::string header_line;
  long time_at = -1, value_at = -1;
  MotionSeries series;
  while (std::getline(in, line)) {
    ++number;
    const std::string_view content = trim(line);
    if (content.empty() || content.front() == '#') continue;
    if (header.empty()) {
      header_line = line;
      header = split(header_line);
      for (std::size_t k = 0; k < header.size(); ++k) {
        if (header[k] == time_column && time_at < 0) time_at = static_cast<long>(k);
        if (header[k] == value_column && value_at < 0) value_at = static_cast<long>(k);
      }
      std::string columns;
      for (const auto& h : header) columns += fmt::format("{}\"{}\"", columns.empty() ? "" : ", ", h);
      for (const auto& [at, column] : {std::pair{time_at, time_column}, std::pair{value_at, value_column}})
        if (at < 0)
          throw MotionError(fmt::format("{}: no column \"{}\" in its header (line {}); its columns are {}", name,
                                        column, number, columns));
      continue;
    }
    const std::vector<std::string_view> cells = split(line);
    double t = 0.0, v = 0.0;
    for (const auto& [at, column, out] :
         {std::tuple{time_at, &time_column, &t}, std::tuple{value_at, &value_column, &v}}) {
      if (static_cast<std::size_t>(at) >= cells.size())
        throw MotionError(fmt::format("{}:{}: the row has {} columns, without \"{}\" (column {})", name, number,
                                      cells.size(), *column, at + 1));
      const std::string_view cell = cells[static_cast<std::size_t>(at)];
      const auto [end, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), *out);
      if (ec != std::errc() || end != cell.data() + cell.size() || !std::isfinite(*out))
        throw MotionError(fmt::format("{}:{}: column \"{}\": '{}' is not a finite number", name, number, *column, cell));
    }
    t += time_offset;
    v *= scale;
    if (!series.times.empty() && !(t > series.times.back()))
      throw MotionError(fmt::format("{}:{}: the time {} does not increase (the row before has {}); expected the rows "
                                    "in increasing time",
                                    name, number, t - time_offset, series.times.back() - time_offset));
    series.times.push_back(t);
    series.values.push_back(v);
  }
  if (header.empty()) throw MotionError(fmt::format("{}: empty; expected a header line naming the columns, then rows", name));
  if (series.times.size() < 2)
    throw MotionError(fmt::format("{}: {} row(s) of data; expected at least two", name, series.times.size()));
  return series;
}

MotionSeries read_motion_csv(const std::filesystem::path& file, const std::string& time_column,
                             const std::string& value_column, double scale, double time_offset) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) throw MotionError(fmt::format("{}: no such file", file.string()));
  if (std::filesystem::is_directory(file, ec))
    throw MotionError(fmt::format("{}: is a directory; expected a CSV file", file.string()));
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in || in.bad()) throw MotionError(fmt::format("{}: cannot be read", file.string()));
  return parse_motion_csv(text.str(), file.string(), time_column, value_column, scale, time_offset);
}

namespace {

template <int Dim>
Vec<3> lift(const Vec<Dim>& v) {
  Vec<3> out{};
  for (int d = 0; d < Dim; ++d) out[d] = v[d];
  return out;
}

template <int Dim>
Vec<Dim> drop(const Vec<3>& v) {
  Vec<Dim> out{};
  for (int d = 0; d < Dim; ++d) out[d] = v[d];
  return out;
}

Vec<3> cross(const Vec<3>& a, const Vec<3>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// Rodrigues' formula: v turned by `angle` about the unit vector a.
Vec<3> rotate(const Vec<3>& a, double angle, const Vec<3>& v) {
  if (angle == 0.0) return v;  // a wall that only translates: what the formula gives, without cos and sin
  const double c = std::cos(angle), s = std::sin(angle);
  return c * v + s * cross(a, v) + ((1.0 - c) * dot(a, v)) * a;
}

}  // namespace

template <int Dim>
BodyState<Dim> body_state(const RigidMotion<Dim>& motion, double t) {
  BodyState<Dim> s;
  s.axis = s.rate_axis = s.acceleration_axis = motion.axis;
  s.centre = motion.centre;
  if (motion.translation) {
    const LawValue l = motion.translation->at(t);
    s.displacement = l.value * motion.direction;
    s.velocity = l.rate * motion.direction;
    s.acceleration = l.acceleration * motion.direction;
  }
  if (motion.rotation) {
    const LawValue l = motion.rotation->at(t);
    s.angle = l.value;
    s.angular_rate = l.rate;
    s.angular_acceleration = l.acceleration;
  }
  return s;
}

template <int Dim>
PointMotion<Dim> point_motion(const BodyState<Dim>& s, const Vec<Dim>& start) {
  const Vec<3> r = rotate(s.axis, s.angle, lift<Dim>(start - s.centre));
  const Vec<3> ar = cross(s.rate_axis, r);
  PointMotion<Dim> m;
  m.position = s.centre + s.displacement + drop<Dim>(r);
  m.velocity = s.velocity + drop<Dim>(s.angular_rate * ar);
  m.acceleration = s.acceleration + drop<Dim>(s.angular_acceleration * cross(s.acceleration_axis, r) +
                                              (s.angular_rate * s.angular_rate) * cross(s.rate_axis, ar));
  return m;
}

template <int Dim>
Vec<Dim> to_start(const BodyState<Dim>& s, const Vec<Dim>& x) {
  return s.centre + drop<Dim>(rotate(s.axis, -s.angle, lift<Dim>(x - s.centre - s.displacement)));
}

template <int Dim>
Vec<Dim> rotate_to_now(const BodyState<Dim>& s, const Vec<Dim>& direction) {
  return drop<Dim>(rotate(s.axis, s.angle, lift<Dim>(direction)));
}

template BodyState<2> body_state<2>(const RigidMotion<2>&, double);
template BodyState<3> body_state<3>(const RigidMotion<3>&, double);
template PointMotion<2> point_motion<2>(const BodyState<2>&, const Vec<2>&);
template PointMotion<3> point_motion<3>(const BodyState<3>&, const Vec<3>&);
template Vec<2> to_start<2>(const BodyState<2>&, const Vec<2>&);
template Vec<3> to_start<3>(const BodyState<3>&, const Vec<3>&);
template Vec<2> rotate_to_now<2>(const BodyState<2>&, const Vec<2>&);
template Vec<3> rotate_to_now<3>(const BodyState<3>&, const Vec<3>&);

}  // namespace sluice
