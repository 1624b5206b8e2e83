// Painting is split into layers: a smooth noise background (float), then anti-aliased shapes
// drawn by OpenCV (8-bit), then a fine grain layer. All randomness comes from the caller's rng.
#include "edge_slam/sim/texture_painter.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace edge_slam {
namespace {

constexpr int kShift = 4;  // sub-texel precision bits for OpenCV drawing
constexpr double kOne = 1 << kShift;

cv::Scalar hsv_to_bgr(double h, double s, double v) {
  h = std::fmod(h, 1.0) * 6.0;
  const int i = static_cast<int>(h);
  const double f = h - i, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  double r, g, b;
  switch (i) {
    case 0: r = v; g = t; b = p; break;
    case 1: r = q; g = v; b = p; break;
    case 2: r = p; g = v; b = t; break;
    case 3: r = p; g = q; b = v; break;
    case 4: r = t; g = p; b = v; break;
    default: r = v; g = p; b = q; break;
  }
  return cv::Scalar(255 * b, 255 * g, 255 * r);
}

// A colour near the surface's palette hue most of the time, sometimes anything at all.
cv::Scalar palette_colour(SplitMix64& rng, double hue) {
  const double h = rng.chance(0.6) ? hue + rng.uniform(-0.08, 0.08) : rng.uniform();
  return hsv_to_bgr(h + 1.0, rng.uniform(0.15, 0.9), rng.uniform(0.08, 0.97));
}

cv::Point to_fixed(double x, double y) {
  return cv::Point(static_cast<int>(std::lround(x * kOne)), static_cast<int>(std::lround(y * kOne)));
}

// Smooth value noise: a coarse random grid upsampled bicubically, added to every channel
// (luminance) with a little per-channel tint.
void add_value_noise(cv::Mat& img32, SplitMix64& rng, double cell, double amplitude) {
  const int gw = std::max(2, static_cast<int>(img32.cols / cell) + 2);
  const int gh = std::max(2, static_cast<int>(img32.rows / cell) + 2);
  cv::Mat grid(gh, gw, CV_32FC3);
  for (int y = 0; y < gh; ++y)
    for (int x = 0; x < gw; ++x) {
      const float l = static_cast<float>(rng.uniform(-1, 1) * amplitude);
      const float tint = static_cast<float>(amplitude * 0.25);
      grid.at<cv::Vec3f>(y, x) = cv::Vec3f(l + tint * static_cast<float>(rng.uniform(-1, 1)),
                                           l + tint * static_cast<float>(rng.uniform(-1, 1)),
                                           l + tint * static_cast<float>(rng.uniform(-1, 1)));
    }
  cv::Mat up;
  cv::resize(grid, up, img32.size(), 0, 0, cell >= 3 ? cv::INTER_CUBIC : cv::INTER_LINEAR);
  img32 += up;
}

cv::Mat noise_background(cv::Size size, SplitMix64& rng, const cv::Scalar& base, double scale_tx) {
  cv::Mat img(size, CV_32FC3, base);
  // Octaves from ~1 m blotches down to ~4 cm mottling.
  for (double cell_m = 1.0, amp = 38; cell_m > 0.03; cell_m *= 0.4, amp *= 0.7)
    add_value_noise(img, rng, cell_m * scale_tx, amp);
  cv::Mat out;
  img.convertTo(out, CV_8UC3);
  return out;
}

void draw_polygon(cv::Mat& img, const std::vector<cv::Point>& pts, const cv::Scalar& c) {
  cv::fillConvexPoly(img, pts, c, cv::LINE_AA, kShift);
}

void draw_rotated_rect(cv::Mat& img, double cx, double cy, double w, double h, double angle,
                       const cv::Scalar& c) {
  const double ca = std::cos(angle), sa = std::sin(angle);
  std::vector<cv::Point> pts;
  for (int k = 0; k < 4; ++k) {
    const double dx = ((k == 0 || k == 3) ? -0.5 : 0.5) * w;
    const double dy = (k < 2 ? -0.5 : 0.5) * h;
    pts.push_back(to_fixed(cx + ca * dx - sa * dy, cy + sa * dx + ca * dy));
  }
  draw_polygon(img, pts, c);
}

// One random shape of roughly `size` texels centred at (cx, cy).
void draw_random_shape(cv::Mat& img, SplitMix64& rng, double cx, double cy, double size,
                       const cv::Scalar& c) {
  switch (rng.integer(0, 5)) {
    case 0:  // axis-aligned rectangle
      draw_rotated_rect(img, cx, cy, size, size * rng.uniform(0.3, 1.5), 0, c);
      break;
    case 1:  // rotated rectangle
      draw_rotated_rect(img, cx, cy, size, size * rng.uniform(0.2, 1.2), rng.uniform(0, M_PI), c);
      break;
    case 2: {  // triangle
      std::vector<cv::Point> pts;
      for (int k = 0; k < 3; ++k)
        pts.push_back(to_fixed(cx + size * rng.uniform(-0.6, 0.6), cy + size * rng.uniform(-0.6, 0.6)));
      draw_polygon(img, pts, c);
      break;
    }
    case 3:  // disc
      cv::circle(img, to_fixed(cx, cy), static_cast<int>(size * 0.5 * kOne), c, cv::FILLED,
                 cv::LINE_AA, kShift);
      break;
    case 4: {  // thick stroke
      const double a = rng.uniform(0, M_PI);
      cv::line(img, to_fixed(cx - std::cos(a) * size * 0.6, cy - std::sin(a) * size * 0.6),
               to_fixed(cx + std::cos(a) * size * 0.6, cy + std::sin(a) * size * 0.6), c,
               std::max(1, static_cast<int>(size * rng.uniform(0.05, 0.2))), cv::LINE_AA, kShift);
      break;
    }
    default: {  // checker patch: many strong corners in a small area
      const int n = rng.integer(2, 4);
      const double cell = size / n;
      const cv::Scalar other = c * 0.35 + cv::Scalar(170, 170, 170) * (rng.chance(0.5) ? 1.0 : 0.0);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          draw_rotated_rect(img, cx + (i - n / 2.0 + 0.5) * cell, cy + (j - n / 2.0 + 0.5) * cell,
                            cell, cell, 0, ((i + j) % 2) ? c : other);
      break;
    }
  }
}

// Shapes with log-uniform sizes between min_m and max_m (more small ones than big ones).
void scatter_shapes(cv::Mat& img, SplitMix64& rng, double tx_per_m, double per_m2, double min_m,
                    double max_m, double hue) {
  const double area = img.cols * img.rows / (tx_per_m * tx_per_m);
  const int count = static_cast<int>(area * per_m2);
  for (int i = 0; i < count; ++i) {
    const double size = min_m * std::pow(max_m / min_m, rng.uniform() * rng.uniform()) * tx_per_m;
    const double cx = rng.uniform(0, img.cols), cy = rng.uniform(0, img.rows);
    draw_random_shape(img, rng, cx, cy, size, palette_colour(rng, hue));
  }
}

// A line of pseudo-characters: each glyph is a few strokes on a 3x4 grid, like printed text.
void draw_glyph_line(cv::Mat& img, SplitMix64& rng, double x0, double y0, double width,
                     double glyph_h, const cv::Scalar& c) {
  const double glyph_w = glyph_h * 0.7;
  const int thickness = std::max(1, static_cast<int>(glyph_h * 0.14));
  for (double x = x0; x + glyph_w < x0 + width; x += glyph_w * 1.25) {
    if (rng.chance(0.15)) continue;  // word gap
    const int strokes = rng.integer(2, 4);
    for (int s = 0; s < strokes; ++s) {
      auto grid_pt = [&]() {
        return to_fixed(x + glyph_w * rng.integer(0, 2) / 2.0, y0 + glyph_h * rng.integer(0, 3) / 3.0);
      };
      cv::line(img, grid_pt(), grid_pt(), c, thickness, cv::LINE_AA, kShift);
    }
  }
}

// A framed poster / label: a contrasting panel filled with shapes and lines of glyph text.
void draw_poster(cv::Mat& img, SplitMix64& rng, double x, double y, double w, double h,
                 double tx_per_m, double hue) {
  const cv::Scalar frame = palette_colour(rng, hue);
  cv::rectangle(img, to_fixed(x - 0.02 * tx_per_m, y - 0.02 * tx_per_m),
                to_fixed(x + w + 0.02 * tx_per_m, y + h + 0.02 * tx_per_m), frame, cv::FILLED,
                cv::LINE_AA, kShift);
  const cv::Scalar paper = hsv_to_bgr(rng.uniform(), rng.uniform(0, 0.3), rng.uniform(0.75, 0.98));
  cv::rectangle(img, to_fixed(x, y), to_fixed(x + w, y + h), paper, cv::FILLED, cv::LINE_AA, kShift);
  const double poster_hue = rng.uniform();
  const int shapes = static_cast<int>(w * h / (tx_per_m * tx_per_m) * 90) + 3;
  for (int i = 0; i < shapes; ++i) {
    const double size = rng.uniform(0.02, 0.25) * std::min(w, h);
    draw_random_shape(img, rng, x + rng.uniform(0.1, 0.9) * w, y + rng.uniform(0.05, 0.6) * h,
                      size, palette_colour(rng, poster_hue));
  }
  const double glyph_h = rng.uniform(0.012, 0.035) * tx_per_m;
  const cv::Scalar ink = hsv_to_bgr(rng.uniform(), rng.uniform(0, 0.8), rng.uniform(0.0, 0.35));
  for (double ly = y + 0.65 * h; ly + glyph_h < y + h * 0.97; ly += glyph_h * 1.7)
    draw_glyph_line(img, rng, x + 0.05 * w, ly, w * rng.uniform(0.5, 0.9), glyph_h, ink);
}

void draw_posters(cv::Mat& img, SplitMix64& rng, double tx, int count, double hue) {
  for (int i = 0; i < count; ++i) {
    const double w = rng.uniform(0.25, 1.1) * tx, h = rng.uniform(0.25, 1.0) * tx;
    if (w >= img.cols || h >= img.rows) continue;
    draw_poster(img, rng, rng.uniform(0, img.cols - w), rng.uniform(0, img.rows - h), w, h, tx, hue);
  }
}

// Floor or ceiling tiles: a grid with per-tile colour jitter and visible grout.
void draw_tiles(cv::Mat& img, SplitMix64& rng, double tile_px, double hue) {
  const cv::Scalar grout = hsv_to_bgr(hue, 0.1, rng.uniform(0.1, 0.3));
  img.setTo(grout);
  const double gap = std::max(1.5, tile_px * 0.04);
  for (double y = 0; y < img.rows; y += tile_px)
    for (double x = 0; x < img.cols; x += tile_px) {
      const cv::Scalar c = hsv_to_bgr(hue + rng.uniform(-0.05, 0.05) + 1.0, rng.uniform(0.1, 0.5),
                                      rng.uniform(0.45, 0.9));
      cv::rectangle(img, to_fixed(x + gap, y + gap), to_fixed(x + tile_px - gap, y + tile_px - gap), c,
                    cv::FILLED, cv::LINE_AA, kShift);
    }
}

// Rows of book spines (vertical stripes of varied width, height and colour) on shelf boards.
void draw_book_shelves(cv::Mat& img, SplitMix64& rng, double tx, double hue) {
  const cv::Scalar board = hsv_to_bgr(0.08, 0.5, rng.uniform(0.25, 0.5));
  const double shelf_h = rng.uniform(0.3, 0.42) * tx;
  for (double y = 0; y < img.rows; y += shelf_h) {
    cv::rectangle(img, to_fixed(0, y), to_fixed(img.cols, y + 0.03 * tx), board, cv::FILLED,
                  cv::LINE_AA, kShift);
    double x = rng.uniform(0, 0.1) * tx;
    while (x < img.cols) {
      const double w = rng.uniform(0.015, 0.06) * tx;
      const double h = rng.uniform(0.6, 0.9) * shelf_h;
      if (!rng.chance(0.1)) {
        const double bottom = y + shelf_h;
        cv::rectangle(img, to_fixed(x, bottom - h), to_fixed(x + w, bottom), palette_colour(rng, hue),
                      cv::FILLED, cv::LINE_AA, kShift);
        if (rng.chance(0.5))
          draw_glyph_line(img, rng, x + w * 0.2, bottom - h * 0.7, w * 0.6, w * 0.5,
                          hsv_to_bgr(0, 0, rng.chance(0.5) ? 0.95 : 0.05));
      }
      x += w + rng.uniform(0, 0.01) * tx;
    }
  }
}

void add_grain(cv::Mat& img, SplitMix64& rng, double tx) {
  cv::Mat f;
  img.convertTo(f, CV_32FC3);
  add_value_noise(f, rng, 0.012 * tx, 9);
  f.convertTo(img, CV_8UC3);
}

}  // namespace

cv::Mat paint_surface(SurfaceStyle style, double width_m, double height_m, double tx,
                      SplitMix64& rng) {
  const cv::Size size(std::max(8, static_cast<int>(std::lround(width_m * tx))),
                      std::max(8, static_cast<int>(std::lround(height_m * tx))));
  const double hue = rng.uniform();
  cv::Mat img = noise_background(size, rng, hsv_to_bgr(hue, rng.uniform(0.1, 0.6), rng.uniform(0.35, 0.8)), tx);
  switch (style) {
    case SurfaceStyle::kWall:
      scatter_shapes(img, rng, tx, 60, 0.03, 0.6, hue);
      draw_posters(img, rng, tx, static_cast<int>(width_m * height_m * 0.35) + 2, hue);
      break;
    case SurfaceStyle::kFloor: {
      cv::Mat tiles(size, CV_8UC3);
      draw_tiles(tiles, rng, rng.uniform(0.3, 0.6) * tx, hue);
      cv::addWeighted(img, 0.35, tiles, 0.65, 0, img);
      scatter_shapes(img, rng, tx, 45, 0.03, 0.5, hue + 0.5);
      // Rugs: large framed rectangles with their own shapes and glyph rows.
      for (int r = 0; r < 2; ++r) {
        const double w = rng.uniform(1.2, 2.2) * tx, h = rng.uniform(0.9, 1.6) * tx;
        draw_poster(img, rng, rng.uniform(0, size.width - w), rng.uniform(0, size.height - h), w, h, tx,
                    rng.uniform());
      }
      break;
    }
    case SurfaceStyle::kCeiling: {
      cv::Mat tiles(size, CV_8UC3);
      draw_tiles(tiles, rng, 0.6 * tx, hue);
      cv::addWeighted(img, 0.4, tiles, 0.6, 0, img);
      scatter_shapes(img, rng, tx, 40, 0.03, 0.4, hue);
      break;
    }
    case SurfaceStyle::kFurniture:
      if (rng.chance(0.5) && height_m > 0.5) draw_book_shelves(img, rng, tx, hue);
      scatter_shapes(img, rng, tx, 70, 0.02, 0.3, hue);
      if (width_m > 0.3 && height_m > 0.3) draw_posters(img, rng, tx, 1 + static_cast<int>(width_m * height_m), hue);
      break;
  }
  add_grain(img, rng, tx);
  return img;
}

}  // namespace edge_slam
