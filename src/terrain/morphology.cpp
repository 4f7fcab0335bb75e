// Square-window erosion, dilation and opening (morphology.h).
#include "terrain/morphology.h"

#include <deque>
#include <vector>

namespace parallax {

namespace {

// out[k * stride] = the extreme of in[(k - r .. k + r) * stride] within [0, n), for k in [0, n):
// a monotone queue of candidates (van Herk / Gil-Werman give the same result with more memory).
template <class Better>
void slide(const double* in, double* out, std::size_t n, std::size_t stride, std::size_t r,
           Better better, std::deque<std::size_t>& queue) {
  queue.clear();
  std::size_t next = 0;  // the next index to enter the window
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t last = k + r < n ? k + r : n - 1;
    for (; next <= last; ++next) {
      while (!queue.empty() && !better(in[queue.back() * stride], in[next * stride])) {
        queue.pop_back();
      }
      queue.push_back(next);
    }
    while (queue.front() + r < k) queue.pop_front();
    out[k * stride] = in[queue.front() * stride];
  }
}

// `better(a, b)`: a stays ahead of b in the queue (strictly more extreme).
template <class Better>
ElevationGrid filter(const ElevationGrid& grid, std::size_t r, Better better) {
  ElevationGrid rows = grid, out = grid;
  std::deque<std::size_t> queue;
  const std::size_t nx = grid.nx(), ny = grid.ny();
  for (std::size_t j = 0; j < ny; ++j) {
    slide(grid.values().data() + j * nx, rows.values().data() + j * nx, nx, 1, r, better, queue);
  }
  for (std::size_t i = 0; i < nx; ++i) {
    slide(rows.values().data() + i, out.values().data() + i, ny, nx, r, better, queue);
  }
  return out;
}

}  // namespace

ElevationGrid erode(const ElevationGrid& grid, std::size_t r) {
  return filter(grid, r, [](double a, double b) { return a < b; });
}

ElevationGrid dilate(const ElevationGrid& grid, std::size_t r) {
  return filter(grid, r, [](double a, double b) { return a > b; });
}

ElevationGrid open(const ElevationGrid& grid, std::size_t r) {
  return dilate(erode(grid, r), r);
}

}  // namespace parallax
