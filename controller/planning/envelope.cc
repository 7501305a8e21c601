#include "controller/planning/envelope.h"

#include <algorithm>
#include <cmath>

#include "plant/vehicle/quasi_steady.h"

namespace scw::controller::planning {
namespace {

// Area under a_x(0) C(r, p) over r in [0, 1] per unit a_x(0) (midpoint rule, 200 cells).
double UnitArea(double p) {
  double a = 0.0;
  for (int k = 0; k < 200; ++k) a += GgvTable::Combine((k + 0.5) / 200.0, p);
  return a / 200.0;
}

// Best (peak, p) inside the samples `d` at kEnvelopeLevels.
void FitOne(const std::array<double, 9>& d, double* peak, double* exponent) {
  double best_area = -1.0;
  *peak = std::max(0.0, d[0]);
  *exponent = 1.0;
  for (int k = 0; k <= 20; ++k) {
    const double p = 1.0 + 0.05 * k;
    double a0 = std::max(0.0, d[0]);
    for (std::size_t j = 1; j < d.size(); ++j) {
      const double c = GgvTable::Combine(kEnvelopeLevels[j], p);
      if (c > 0.0) a0 = std::min(a0, std::max(0.0, d[j]) / c);
    }
    const double area = a0 * UnitArea(p);
    if (area > best_area + 1e-12) {
      best_area = area;
      *peak = a0;
      *exponent = p;
    }
  }
}

}  // namespace

std::vector<EnvelopeRow> SampleEnvelope(const params::VehicleParams& v, double brake_bias_front,
                                        const std::vector<double>& speeds) {
  plant::QuasiSteadyOptions o;
  o.brake_bias_front = brake_bias_front;
  params::VehicleParams ideal = v;
  ideal.sensors.noise = false;
  const plant::QuasiSteadyModel qs(ideal, o);
  std::vector<EnvelopeRow> rows;
  for (double s : speeds) {
    EnvelopeRow r;
    r.speed = s;
    r.ay_max = qs.MaxLateral(s);
    for (std::size_t j = 0; j < kEnvelopeLevels.size(); ++j) {
      const double ay = kEnvelopeLevels[j] * r.ay_max;
      r.drive[j] = qs.MaxDrive(s, ay);
      r.brake[j] = qs.MaxBrake(s, ay);
    }
    rows.push_back(r);
  }
  return rows;
}

GgvTable FitEnvelope(const std::vector<EnvelopeRow>& rows) {
  GgvTable g = GgvTable::Empty();
  for (const EnvelopeRow& r : rows) {
    double d0 = 0.0, pd = 1.0, b0 = 0.0, pb = 1.0;
    FitOne(r.drive, &d0, &pd);
    FitOne(r.brake, &b0, &pb);
    g.speed.push_back(r.speed);
    g.ay_max.push_back(std::max(r.ay_max, 1.0));
    g.ax_drive_max.push_back(d0);
    g.ax_brake_max.push_back(std::max(b0, 1.0));
    g.drive_exponent.push_back(pd);
    g.brake_exponent.push_back(pb);
  }
  g.Validate("plant envelope");
  return g;
}

GgvTable PlantEnvelope(const params::VehicleParams& v, double brake_bias_front) {
  // Combined rows every 10 m/s (the expensive part) give the shape: exponent and the fitted
  // peak's share of the pure limit. The pure limits themselves vary strongly with speed (power
  // limit ~1/v, downforce ~v^2), so they are sampled every 2 m/s and the shape is interpolated.
  std::vector<double> knots;
  for (double s = 10.0; s <= 90.0; s += 10.0) knots.push_back(s);
  const std::vector<EnvelopeRow> rows = SampleEnvelope(v, brake_bias_front, knots);
  const GgvTable coarse = FitEnvelope(rows);
  std::vector<double> pure_drive, pure_brake;
  for (const EnvelopeRow& r : rows) {
    pure_drive.push_back(r.drive[0]);
    pure_brake.push_back(r.brake[0]);
  }
  GgvTable share = coarse;  // ax columns as fitted peak / pure limit
  for (std::size_t i = 0; i < knots.size(); ++i) {
    share.ax_drive_max[i] = pure_drive[i] > 0.0 ? coarse.ax_drive_max[i] / pure_drive[i] : 1.0;
    share.ax_brake_max[i] = pure_brake[i] > 0.0 ? coarse.ax_brake_max[i] / pure_brake[i] : 1.0;
  }
  plant::QuasiSteadyOptions o;
  o.brake_bias_front = brake_bias_front;
  params::VehicleParams ideal = v;
  ideal.sensors.noise = false;
  const plant::QuasiSteadyModel qs(ideal, o);
  GgvTable g = GgvTable::Empty();
  // Between two 10 m/s knots the more conservative shape of the two applies.
  auto knot_min = [&](const std::vector<double>& col, double sp) {
    const double lo = std::clamp(std::floor(sp / 10.0) * 10.0, knots.front(), knots.back());
    const double hi = std::clamp(std::ceil(sp / 10.0) * 10.0, knots.front(), knots.back());
    auto at = [&](double k) { return col[static_cast<std::size_t>(std::lround(k / 10.0)) - 1]; };
    return std::min(at(lo), at(hi));
  };
  // The pure drive limit steps down at every upshift: the value at each 2 m/s node is at most the
  // smallest engine-limited acceleration over its neighbourhood (0.5 m/s samples of the engine's
  // full-load force less drag and rolling resistance), so the interpolation never exceeds it.
  auto engine_accel = [&](double x) {
    return (qs.MaxEngineForce(x) - qs.RoadLoad(x)) / ideal.chassis.mass;
  };
  auto pure_drive_min = [&](double sp) {
    double d = qs.MaxDrive(sp, 0.0);
    for (double x = sp - 2.0; x <= sp + 2.0 + 1e-9; x += 0.5)
      if (x >= 5.0) d = std::min(d, std::max(0.0, engine_accel(x)));
    return d;
  };
  for (double sp = 10.0; sp <= 90.0 + 1e-9; sp += 2.0) {
    g.speed.push_back(sp);
    g.ay_max.push_back(std::max(qs.MaxLateral(sp), 1.0));
    g.ax_drive_max.push_back(pure_drive_min(sp) * knot_min(share.ax_drive_max, sp));
    g.ax_brake_max.push_back(
        std::max(qs.MaxBrake(sp, 0.0) * knot_min(share.ax_brake_max, sp), 1.0));
    g.drive_exponent.push_back(knot_min(coarse.drive_exponent, sp));
    g.brake_exponent.push_back(knot_min(coarse.brake_exponent, sp));
  }
  g.Validate("plant envelope");
  return g;
}

}  // namespace scw::controller::planning
