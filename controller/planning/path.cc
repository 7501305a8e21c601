#include "controller/planning/path.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "params/schema/field.h"
#include "plant/common/fast_math.h"

namespace scw::controller::planning {

double WrapAngle(double a) noexcept {
  if (!std::isfinite(a)) return 0.0;
  // remainder(a, 2π) is exact and returns a itself for |a| ≤ π (the quotient rounds to 0, ties to
  // even), so the library call is only needed outside that range.
  if (!(a >= -M_PI && a <= M_PI)) a = std::remainder(a, 2.0 * M_PI);
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}

Path::Path(std::vector<PathPoint> points, double length)
    : points_(std::move(points)), length_(length) {
  using params::FormatNumber;
  const auto station = [](std::size_t i) { return "stations[" + std::to_string(i) + "]"; };
  Problems pr;
  if (points_.size() < 3)
    pr.Add("stations", "needs at least 3 stations, has " + std::to_string(points_.size()));
  if (!points_.empty() && points_.front().s != 0.0)
    pr.Add(station(0) + ".s",
           "must be 0 (a path starts at s = 0), is " + FormatNumber(points_.front().s));
  for (std::size_t i = 1; i < points_.size(); ++i)
    if (!(points_[i].s > points_[i - 1].s)) {
      pr.Add(station(i) + ".s",
             "must exceed the s of the station before (the first station out "
             "of order)");
      break;
    }
  if (!points_.empty() && !(length_ > points_.back().s))
    pr.Add("length", "must exceed the s of the last station (" + FormatNumber(points_.back().s) +
                         " m), is " + FormatNumber(length_));
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const PathPoint& p = points_[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.psi) ||
        !std::isfinite(p.kappa) || !std::isfinite(p.v) || !std::isfinite(p.a_x)) {
      pr.Add(station(i), "has a non-finite x, y, psi, kappa, v or a_x (the first such station)");
      break;
    }
  }
  if (!pr.empty()) throw ConfigError("reference path", pr.items());
  mean_ds_ = length_ / static_cast<double>(points_.size());
  const std::size_t n = points_.size();
  for (auto* v : {&seg_ax_, &seg_ay_, &seg_ex_, &seg_ey_, &seg_len2_}) v->resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const PathPoint& a = points_[i];
    const PathPoint& b = points_[i + 1 == n ? 0 : i + 1];
    const double ex = b.x - a.x, ey = b.y - a.y;
    seg_ax_[i] = a.x;
    seg_ay_[i] = a.y;
    seg_ex_[i] = ex;
    seg_ey_[i] = ey;
    seg_len2_[i] = ex * ex + ey * ey;
  }
  // Each block's circle: the centre of the bounding box of its segments' end stations, the
  // largest distance to one of them as radius (a segment lies in the hull of its ends).
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  for (auto* v : {&blk_cx_, &blk_cy_, &blk_r_}) v->resize(blocks);
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t lo = b * kBlock, hi = std::min(n, lo + kBlock);  // stations lo … hi
    const auto at = [&](std::size_t k) -> const PathPoint& { return points_[k % n]; };
    double x0 = at(lo).x, x1 = x0, y0 = at(lo).y, y1 = y0;
    for (std::size_t k = lo + 1; k <= hi; ++k) {
      x0 = std::min(x0, at(k).x);
      x1 = std::max(x1, at(k).x);
      y0 = std::min(y0, at(k).y);
      y1 = std::max(y1, at(k).y);
    }
    const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    double r = 0.0;
    for (std::size_t k = lo; k <= hi; ++k) r = std::max(r, std::hypot(at(k).x - cx, at(k).y - cy));
    blk_cx_[b] = cx;
    blk_cy_[b] = cy;
    blk_r_[b] = r;
  }
}

double Path::Wrap(double s) const noexcept {
  if (s >= 0 && s < length_) return s;  // what fmod gives on [0, length), without the call
  if (!std::isfinite(s)) return 0.0;
  double w = std::fmod(s, length_);
  if (w < 0) w += length_;
  return w >= length_ ? 0.0 : w;
}

std::size_t Path::SegmentAt(double s) const noexcept {
  // Stations are near-uniform: start from the estimate and walk.
  const std::size_t n = points_.size();
  std::size_t i = std::min(n - 1, static_cast<std::size_t>(s / mean_ds_));
  while (i > 0 && points_[i].s > s) --i;
  while (i + 1 < n && points_[i + 1].s <= s) ++i;
  return i;
}

PathPoint Path::Sample(double s_in) const noexcept {
  const double s = Wrap(s_in);
  const std::size_t i = SegmentAt(s);
  const std::size_t j = i + 1 == points_.size() ? 0 : i + 1;
  const PathPoint& a = points_[i];
  const PathPoint& b = points_[j];
  const double s_b = j == 0 ? length_ : b.s;
  const double t = (s - a.s) / (s_b - a.s);
  PathPoint p;
  p.s = s;
  p.x = a.x + t * (b.x - a.x);
  p.y = a.y + t * (b.y - a.y);
  p.psi = WrapAngle(a.psi + t * WrapAngle(b.psi - a.psi));
  p.kappa = a.kappa + t * (b.kappa - a.kappa);
  p.v = a.v + t * (b.v - a.v);
  p.a_x = a.a_x + t * (b.a_x - a.a_x);
  return p;
}

PathProjection Path::Project(double x, double y, double psi, double s_hint,
                             double window) const noexcept {
  const std::size_t n = points_.size();
  std::size_t first = 0, count = n;
  if (std::isfinite(s_hint) && s_hint >= 0 && window > 0 && 2 * window < length_) {
    const std::size_t half = static_cast<std::size_t>(window / mean_ds_) + 2;
    const std::size_t center = SegmentAt(Wrap(s_hint));
    first = center + n - std::min(half, n);  // < 2n: one conditional subtraction is the modulo
    if (first >= n) first -= n;
    count = std::min(n, 2 * half + 1);
  }

  // Segment k joins station k to k + 1; segment n − 1 closes the loop back to station 0. Only
  // the closest segment's index, parameter t and squared distance are kept.
  double best_d2 = std::numeric_limits<double>::infinity();
  double best_t = 0.0;
  std::size_t best_i = 0;
  // Two segments per Double2, each lane the scalar expressions in their order; the closest is
  // then taken lane by lane in scan order (the strict < keeps the first of equals).
  using plant::Double2;
  using plant::fast_math_detail::Select;
  using plant::fast_math_detail::Splat;
  const Double2 qx = Splat(x), qy = Splat(y), zero = Splat(0.0), one = Splat(1.0);
  const auto load = [](const std::vector<double>& v, std::size_t i) {
    return Double2{v[i], v[i + 1]};
  };
  // Segment i's squared distance to (x, y) and the parameter t of its closest point (scalar).
  const auto foot = [&](std::size_t i, double* t_out) {
    const double ax = seg_ax_[i], ay = seg_ay_[i], ex = seg_ex_[i], ey = seg_ey_[i],
                 len2 = seg_len2_[i];
    double t = len2 > 0 ? ((x - ax) * ex + (y - ay) * ey) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    const double px = ax + t * ex, py = ay + t * ey;
    *t_out = t;
    return (x - px) * (x - px) + (y - py) * (y - py);
  };
  const auto scan_segments = [&](std::size_t from, std::size_t to) {  // segments [from, to)
    std::size_t i = from;
    for (; i + 1 < to; i += 2) {
      const Double2 ax = load(seg_ax_, i), ay = load(seg_ay_, i), ex = load(seg_ex_, i),
                    ey = load(seg_ey_, i), len2 = load(seg_len2_, i);
      Double2 t = Select<Double2>(len2 > zero, ((qx - ax) * ex + (qy - ay) * ey) / len2, zero);
      t = Select<Double2>(t < zero, zero, Select<Double2>(one < t, one, t));
      const Double2 px = ax + t * ex, py = ay + t * ey;
      const Double2 d2 = (qx - px) * (qx - px) + (qy - py) * (qy - py);
      for (std::size_t l = 0; l < 2; ++l)
        if (d2[l] < best_d2) {
          best_d2 = d2[l];
          best_t = t[l];
          best_i = i + l;
        }
    }
    for (; i < to; ++i) {
      double t = 0.0;
      const double d2 = foot(i, &t);
      if (d2 < best_d2) {
        best_d2 = d2;
        best_t = t;
        best_i = i;
      }
    }
  };
  // A block is skipped when even its circle is farther than `bound`, the smaller of the closest
  // distance found so far and that of the hint's segment (a distance some segment of the window
  // has): a skipped segment is then strictly farther than the closest one, so the scan's result,
  // the first closest segment in scan order, is the same as without skipping. The margin (1 µm,
  // and 1e-12 of the coordinates' size) covers the rounding of the circle test and of the
  // segments' own distances by orders of magnitude; non-finite values never skip.
  double bound = std::numeric_limits<double>::infinity();
  if (count < n) {
    const std::size_t c = first + count / 2 < n ? first + count / 2 : first + count / 2 - n;
    double t_c = 0.0;
    bound = foot(c, &t_c);
  }
  const double slack = 1e-6 + 1e-12 * (std::abs(x) + std::abs(y));
  const auto scan = [&](std::size_t from, std::size_t to) {
    while (from < to) {
      const std::size_t b = from / kBlock, stop = std::min(to, (b + 1) * kBlock);
      const double cx = blk_cx_[b], cy = blk_cy_[b];
      const double gap = std::sqrt((x - cx) * (x - cx) + (y - cy) * (y - cy)) - blk_r_[b] -
                         (slack + 1e-12 * (std::abs(cx) + std::abs(cy)));
      const double closest = std::min(bound, best_d2);
      if (!(gap > 0.0 && gap * gap > closest)) scan_segments(from, stop);
      from = stop;
    }
  };
  // The window, segments first, first + 1, … (count of them, modulo n), in that order: at most
  // two runs of plain indices around the end of the loop.
  const std::size_t end = first + count;  // one past the window's last segment, unwrapped
  scan(first, std::min(end, n));
  if (end > n) scan(0, end - n);
  const PathPoint* const p = points_.data();

  // Nothing closer than infinity (non-finite input): the default projection, as before.
  PathProjection best;
  if (!(best_d2 < std::numeric_limits<double>::infinity())) return best;
  // The outputs of the closest segment, by the same expressions the scan used.
  const std::size_t i = best_i, j = i + 1 == n ? 0 : i + 1;
  const PathPoint& a = p[i];
  const PathPoint& b = p[j];
  const double t = best_t;
  const double ex = b.x - a.x, ey = b.y - a.y;
  const double s_b = j == 0 ? length_ : b.s;
  best.s = Wrap(a.s + t * (s_b - a.s));
  best.segment = i;
  const double cross = ex * (y - a.y) - ey * (x - a.x);
  best.lateral_error = (cross >= 0 ? 1.0 : -1.0) * std::sqrt(best_d2);
  best.heading_error = WrapAngle(psi - (a.psi + t * WrapAngle(b.psi - a.psi)));
  return best;
}

}  // namespace scw::controller::planning
