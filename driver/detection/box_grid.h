#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <unordered_map>
#include <vector>

/// The broad phase of the contact detection, in either dimension: axis-
/// aligned boxes binned on a uniform grid. The same code finds the near
/// pairs of bodies (2D and 3D) and, in 3D, the boundary triangles near a
/// node (detection_3d.h).
namespace softpack::dynamics
{

/// An axis-aligned box in D dimensions.
template <int D> struct Box
{
  std::array<double, D> lo, hi;

  /// The boxes, each inflated by `margin`, overlap
  bool overlaps(const Box& o, double margin) const
  {
    for (int d = 0; d < D; ++d)
      if (!(lo[d] - margin <= o.hi[d] && o.lo[d] - margin <= hi[d]))
        return false;
    return true;
  }
  /// The point p (D coordinates) lies in the box inflated by `margin`
  bool contains(const double* p, double margin) const
  {
    for (int d = 0; d < D; ++d)
      if (!(p[d] >= lo[d] - margin && p[d] <= hi[d] + margin))
        return false;
    return true;
  }
  /// Largest edge
  double extent() const
  {
    double e = 0;
    for (int d = 0; d < D; ++d)
      e = std::max(e, hi[d] - lo[d]);
    return e;
  }
  /// The empty box (grows to the first point added)
  static Box empty()
  {
    constexpr double inf = std::numeric_limits<double>::infinity();
    Box b;
    b.lo.fill(inf);
    b.hi.fill(-inf);
    return b;
  }
  /// Grow to contain the point p (D coordinates)
  void add(const double* p)
  {
    for (int d = 0; d < D; ++d)
    {
      lo[d] = std::min(lo[d], p[d]);
      hi[d] = std::max(hi[d], p[d]);
    }
  }
};

/// The box of points of x (D interleaved coordinates per point): point
/// storage[i] for each i in `points` (a body's boundary nodes as local
/// indices into its nodes), or point i itself when `storage` is empty.
template <int D>
Box<D> points_box(std::span<const double> x,
                  std::span<const std::int32_t> points,
                  std::span<const std::int32_t> storage)
{
  Box<D> box = Box<D>::empty();
  for (std::int32_t p : points)
    box.add(&x[D * static_cast<std::size_t>(storage.empty() ? p : storage[p])]);
  return box;
}

/// Boxes binned on a uniform grid by their lower corners (cell = the
/// largest box extent plus the margin): a box spans at most two cells per
/// direction, so the boxes that a box of the same set, or a point, touches
/// within `margin` are binned in the 3^D cells around its bin. The cost of
/// building and of all the queries grows linearly with the boxes.
template <int D> class BoxGrid
{
public:
  using Cell = std::array<std::int64_t, D>;

  BoxGrid(const std::vector<Box<D>>& boxes, double margin)
      : _min(boxes.at(0).lo)
  {
    for (const Box<D>& b : boxes)
      for (int d = 0; d < D; ++d)
      {
        _cell = std::max(_cell, b.hi[d] - b.lo[d] + margin);
        _min[d] = std::min(_min[d], b.lo[d]);
      }
    if (!(_cell > 0)) // points only, no margin: any cell size bins them
      _cell = 1;
    for (std::size_t b = 0; b < boxes.size(); ++b)
      _grid[bin(boxes[b].lo.data())].push_back(static_cast<int>(b));
  }

  /// Call f(index) for every box binned in the 3^D cells around the bin
  /// of the point p (the lower corner of a query box); each box once
  template <typename F> void near(const double* p, F f) const
  {
    const Cell c = bin(p);
    Cell k;
    for (int i = 0; i < num_neighbours; ++i)
    {
      int r = i;
      for (int d = D - 1; d >= 0; --d, r /= 3)
        k[d] = c[d] + r % 3 - 1;
      auto it = _grid.find(k);
      if (it != _grid.end())
        for (int b : it->second)
          f(b);
    }
  }

private:
  static constexpr int num_neighbours = D == 2 ? 9 : 27;
  struct Hash
  {
    std::size_t operator()(const Cell& c) const
    {
      std::uint64_t h = 0;
      for (int d = 0; d < D; ++d)
        h = h * 0x9E3779B97F4A7C15ull + static_cast<std::uint64_t>(c[d]);
      return static_cast<std::size_t>(h ^ (h >> 29));
    }
  };
  Cell bin(const double* p) const
  {
    Cell c;
    for (int d = 0; d < D; ++d)
      c[d] = static_cast<std::int64_t>((p[d] - _min[d]) / _cell);
    return c;
  }
  double _cell = 0;
  std::array<double, D> _min;
  std::unordered_map<Cell, std::vector<int>, Hash> _grid;
};

/// Pairs (i < j) of the boxes whose inflations by `margin` overlap, in
/// increasing order (the order does not depend on the grid's).
template <int D>
std::vector<std::array<int, 2>>
overlapping_pairs(const std::vector<Box<D>>& boxes, double margin)
{
  if (boxes.empty())
    return {};
  const BoxGrid<D> grid(boxes, margin);
  std::vector<std::array<int, 2>> pairs;
  for (std::size_t a = 0; a < boxes.size(); ++a)
    grid.near(boxes[a].lo.data(),
              [&](int b)
              {
                if (b > static_cast<int>(a) &&
                    boxes[a].overlaps(boxes[b], margin))
                  pairs.push_back({static_cast<int>(a), b});
              });
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

} // namespace softpack::dynamics
