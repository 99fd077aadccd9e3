#include "renders/image.hpp"

#include <png.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace tumble::render {

void write_png(const std::filesystem::path& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * image.height * 3) {
    throw std::invalid_argument("write_png: image buffer does not match its size");
  }
  const std::filesystem::path temporary =
      path.string() + ".tmp-" + std::to_string(::getpid()) + ".png";
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGB;
  if (png_image_write_to_file(&png, temporary.c_str(), 0, image.rgb.data(), 0, nullptr) == 0) {
    const std::string reason = png.message;
    png_image_free(&png);
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error(path.string() + ": cannot write PNG (" + reason + ")");
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::filesystem::remove(temporary, ec);
    throw std::runtime_error(path.string() + ": cannot write PNG (rename failed)");
  }
}

Image read_png(const std::filesystem::path& path) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_file(&png, path.c_str()) == 0) {
    const std::string reason = png.message;
    png_image_free(&png);
    throw std::runtime_error(path.string() + ": cannot read PNG (" + reason + ")");
  }
  png.format = PNG_FORMAT_RGB;
  Image image(static_cast<int>(png.width), static_cast<int>(png.height));
  if (png_image_finish_read(&png, nullptr, image.rgb.data(), 0, nullptr) == 0) {
    const std::string reason = png.message;
    png_image_free(&png);
    throw std::runtime_error(path.string() + ": cannot read PNG (" + reason + ")");
  }
  return image;
}

ImageDifference compare_images(const Image& a, const Image& b, int pixel_threshold) {
  if (a.width != b.width || a.height != b.height || a.rgb.size() != b.rgb.size()) {
    throw std::invalid_argument("compare_images: sizes differ (" + std::to_string(a.width) + "x" +
                                std::to_string(a.height) + " vs " + std::to_string(b.width) + "x" +
                                std::to_string(b.height) + ")");
  }
  ImageDifference d;
  const std::size_t pixels = a.rgb.size() / 3;
  if (pixels == 0)
    return d;
  long long total = 0;
  std::size_t different = 0;
  for (std::size_t p = 0; p < pixels; ++p) {
    int worst = 0;
    for (int c = 0; c < 3; ++c) {
      const int diff = std::abs(int(a.rgb[p * 3 + c]) - int(b.rgb[p * 3 + c]));
      total += diff;
      worst = std::max(worst, diff);
    }
    d.max_absolute = std::max(d.max_absolute, worst);
    if (worst > pixel_threshold)
      ++different;
  }
  d.mean_absolute = static_cast<double>(total) / static_cast<double>(pixels * 3);
  d.fraction_different = static_cast<double>(different) / static_cast<double>(pixels);
  return d;
}

}  // namespace tumble::render
