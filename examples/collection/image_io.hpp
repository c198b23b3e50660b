// examples/collection/image_io.hpp — 8-bit grayscale images, a PNG encoder, atomic file writes.
//
// The encoder is self-contained (no OpenCV): deflate via zlib when LIESERVO_COLLECT_HAVE_ZLIB
// is defined, otherwise uncompressed ("stored") deflate blocks — valid PNG either way, and
// byte-for-byte deterministic for a given image.
#pragma once

#include <lieservo_dataset/json.hpp>  // DatasetError

#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#if defined(LIESERVO_COLLECT_HAVE_ZLIB)
#include <zlib.h>
#endif
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

namespace detail {

inline std::uint32_t crc32(const std::uint8_t* data, std::size_t n, std::uint32_t crc = 0) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1U) ? 0xEDB88320U ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  crc = ~crc;
  for (std::size_t i = 0; i < n; ++i) crc = table[(crc ^ data[i]) & 0xFFU] ^ (crc >> 8);
  return ~crc;
}

inline void putBe32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  out.push_back(static_cast<std::uint8_t>(v >> 24));
  out.push_back(static_cast<std::uint8_t>(v >> 16));
  out.push_back(static_cast<std::uint8_t>(v >> 8));
  out.push_back(static_cast<std::uint8_t>(v));
}

inline void putChunk(std::vector<std::uint8_t>& out, const char type[5], const std::vector<std::uint8_t>& data) {
  putBe32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  putBe32(out, crc32(out.data() + start, out.size() - start));
}

inline std::vector<std::uint8_t> zlibStream(const std::vector<std::uint8_t>& raw) {
#if defined(LIESERVO_COLLECT_HAVE_ZLIB)
  uLongf n = compressBound(static_cast<uLong>(raw.size()));
  std::vector<std::uint8_t> out(n);
  if (compress2(out.data(), &n, raw.data(), static_cast<uLong>(raw.size()), 6) != Z_OK) {
    throw DatasetError("PNG encoder: zlib compress2 failed");
  }
  out.resize(n);
  return out;
#else
  std::vector<std::uint8_t> out = {0x78, 0x01};  // zlib header, no compression
  std::size_t pos = 0;
  do {
    const std::size_t len = raw.size() - pos < 65535 ? raw.size() - pos : 65535;
    out.push_back(pos + len == raw.size() ? 1 : 0);  // BFINAL, BTYPE = 00 (stored)
    out.push_back(static_cast<std::uint8_t>(len));
    out.push_back(static_cast<std::uint8_t>(len >> 8));
    out.push_back(static_cast<std::uint8_t>(~len));
    out.push_back(static_cast<std::uint8_t>(~len >> 8));
    out.insert(out.end(), raw.begin() + static_cast<std::ptrdiff_t>(pos),
               raw.begin() + static_cast<std::ptrdiff_t>(pos + len));
    pos += len;
  } while (pos < raw.size());
  std::uint32_t a = 1, b = 0;  // Adler-32
  for (const std::uint8_t c : raw) {
    a = (a + c) % 65521U;
    b = (b + a) % 65521U;
  }
  putBe32(out, (b << 16) | a);
  return out;
#endif
}

}  // namespace detail

/// PNG bytes of an 8-bit grayscale image (colour type 0, no filtering, no interlace).
inline std::vector<std::uint8_t> encodePngGray8(const GrayImage& img) {
  if (!img.valid()) throw DatasetError("PNG encoder: invalid image size");
  std::vector<std::uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  std::vector<std::uint8_t> ihdr;
  detail::putBe32(ihdr, static_cast<std::uint32_t>(img.width));
  detail::putBe32(ihdr, static_cast<std::uint32_t>(img.height));
  ihdr.insert(ihdr.end(), {8, 0, 0, 0, 0});  // depth 8, grayscale, deflate, filter 0, no interlace
  detail::putChunk(out, "IHDR", ihdr);
  std::vector<std::uint8_t> raw;
  raw.reserve(static_cast<std::size_t>(img.height) * (static_cast<std::size_t>(img.width) + 1));
  for (int r = 0; r < img.height; ++r) {
    raw.push_back(0);  // filter: none
    const auto* row = img.pixels.data() + static_cast<std::size_t>(r) * static_cast<std::size_t>(img.width);
    raw.insert(raw.end(), row, row + img.width);
  }
  detail::putChunk(out, "IDAT", detail::zlibStream(raw));
  detail::putChunk(out, "IEND", {});
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
