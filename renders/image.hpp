// 8-bit RGB images: PNG reading and writing (libpng's simplified API) and the per-pixel
// comparison the reference-image tests use.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace tumble::render {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  // row-major from the top row, 3 bytes per pixel

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3) {}
};

// Writes `image` as a PNG to a temporary name beside `path` and renames it onto `path`, so an
// interrupted write never leaves a truncated file. Throws std::runtime_error naming the path.
void write_png(const std::filesystem::path& path, const Image& image);

// Reads any PNG as 8-bit RGB. Throws std::runtime_error naming the path.
Image read_png(const std::filesystem::path& path);

// How far apart two images of the same size are.
struct ImageDifference {
  double mean_absolute = 0;       // over every channel of every pixel, in 0..255
  double fraction_different = 0;  // pixels with some channel off by more than the threshold
  int max_absolute = 0;           // largest channel difference, 0..255
};

// Throws std::invalid_argument when the sizes differ.
ImageDifference compare_images(const Image& a, const Image& b, int pixel_threshold);

}  // namespace tumble::render
