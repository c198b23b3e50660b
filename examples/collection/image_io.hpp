// examples/collection/image_io.hpp — 8-bit grayscale images, PNG encoding (libpng), atomic
// file writes.
#pragma once

#include <lieservo_dataset/json.hpp>  // DatasetError

#include <png.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#if defined(__unix__) || defined(__APPLE__)
#include <fcntl.h>
#include <unistd.h>
#endif

namespace lieservo::collection {

// The JSON and data set readers are the shared ones of examples/dataset.
using namespace lieservo::dataset;

/// Row-major 8-bit grayscale image.
struct GrayImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;  ///< width·height bytes, row-major

  GrayImage() = default;
  GrayImage(int w, int h, std::uint8_t fill = 0)
      : width(w), height(h), pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), fill) {}
  std::uint8_t& at(int row, int col) { return pixels[static_cast<std::size_t>(row) * static_cast<std::size_t>(width) + static_cast<std::size_t>(col)]; }
  std::uint8_t at(int row, int col) const { return pixels[static_cast<std::size_t>(row) * static_cast<std::size_t>(width) + static_cast<std::size_t>(col)]; }
  bool valid() const {
    return width > 0 && height > 0 &&
           pixels.size() == static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  }
};

/// PNG bytes of an 8-bit grayscale image, by libpng's simplified API (deterministic for a
/// given image). Throws DatasetError for an invalid image or a libpng failure.
inline std::vector<std::uint8_t> encodePngGray8(const GrayImage& img) {
  if (!img.valid()) throw DatasetError("PNG encoder: invalid image size");
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(img.width);
  image.height = static_cast<png_uint_32>(img.height);
  image.format = PNG_FORMAT_GRAY;
  png_alloc_size_t size = 0;  // first call: the size the PNG needs
  if (!png_image_write_to_memory(&image, nullptr, &size, 0, img.pixels.data(), img.width, nullptr)) {
    const std::string why = image.message;
    png_image_free(&image);
    throw DatasetError("PNG encoder: " + why);
  }
  std::vector<std::uint8_t> out(size);
  if (!png_image_write_to_memory(&image, out.data(), &size, 0, img.pixels.data(), img.width, nullptr)) {
    const std::string why = image.message;
    png_image_free(&image);
    throw DatasetError("PNG encoder: " + why);
  }
  out.resize(size);
  return out;
}

/// The 8-bit grayscale image a PNG holds (any PNG, converted by libpng). Throws DatasetError
/// naming libpng's reason when it cannot be decoded.
inline GrayImage decodePngGray8(const std::vector<std::uint8_t>& png) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&image, png.data(), png.size()))
    throw DatasetError(std::string("PNG decoder: ") + image.message);
  image.format = PNG_FORMAT_GRAY;
  GrayImage out(static_cast<int>(image.width), static_cast<int>(image.height));
  if (!png_image_finish_read(&image, nullptr, out.pixels.data(), out.width, nullptr)) {
    const std::string why = image.message;
    png_image_free(&image);
    throw DatasetError("PNG decoder: " + why);
  }
  return out;
}

/// Write bytes to `path` atomically: write `path`.tmp, flush and fsync, then rename over
/// `path`. A reader (or a resumed run) sees either the old file or the complete new one.
inline void writeFileAtomic(const std::string& path, const void* data, std::size_t n) {
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr) throw DatasetError(tmp + ": error: cannot open for writing");
  const bool ok = std::fwrite(data, 1, n, f) == n && std::fflush(f) == 0;
#if defined(__unix__) || defined(__APPLE__)
  const bool synced = ok && ::fsync(::fileno(f)) == 0;
#else
  const bool synced = ok;
#endif
  if (std::fclose(f) != 0 || !synced) {
    std::remove(tmp.c_str());
    throw DatasetError(tmp + ": error: write failed");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw DatasetError(path + ": error: rename from .tmp failed: " + ec.message());
}

inline void writeFileAtomic(const std::string& path, const std::string& text) {
  writeFileAtomic(path, text.data(), text.size());
}

inline void writePngAtomic(const std::string& path, const GrayImage& img) {
  const std::vector<std::uint8_t> png = encodePngGray8(img);
  writeFileAtomic(path, png.data(), png.size());
}

}  // namespace lieservo::collection
