// Checks the viewer's screenshots for its test (test_viewer.sh).
//
//   image_check coverage IMAGE MIN MAX   the fraction of pixels that differ from the
//                                        background (the top-left pixel's colour) is
//                                        in [MIN, MAX]
//   image_check differ A B MIN           A and B have the same size and at least the
//                                        fraction MIN of their pixels differ
//
// Prints what it measured; exits 0 when the check holds, 1 otherwise.
#include <stb_image.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

namespace {

struct Image {
  int w = 0, h = 0;
  std::unique_ptr<unsigned char, void (*)(void*)> data{nullptr, stbi_image_free};
  const unsigned char* pixel(int i) const { return data.get() + 3 * static_cast<long>(i); }
};

Image load(const char* path) {
  Image img;
  int channels = 0;
  img.data.reset(stbi_load(path, &img.w, &img.h, &channels, 3));
  if (!img.data) {
    std::fprintf(stderr, "image_check: %s: cannot read (%s)\n", path, stbi_failure_reason());
    std::exit(1);
  }
  return img;
}

// A few levels of tolerance absorb antialiasing and compression noise.
bool differs(const unsigned char* a, const unsigned char* b) {
  for (int k = 0; k < 3; ++k)
    if (std::abs(int(a[k]) - int(b[k])) > 4) return true;
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 5 && !std::strcmp(argv[1], "coverage")) {
    const Image img = load(argv[2]);
    const double lo = std::atof(argv[3]), hi = std::atof(argv[4]);
    long covered = 0;
    const long n = static_cast<long>(img.w) * img.h;
    for (long i = 0; i < n; ++i) covered += differs(img.pixel(static_cast<int>(i)), img.pixel(0));
    const double f = static_cast<double>(covered) / n;
    std::printf("%s: %dx%d, %.1f%% of the pixels are not background\n", argv[2], img.w, img.h,
                100 * f);
    return f >= lo && f <= hi ? 0 : 1;
  }
  if (argc == 5 && !std::strcmp(argv[1], "differ")) {
    const Image a = load(argv[2]), b = load(argv[3]);
    if (a.w != b.w || a.h != b.h) {
      std::printf("%s and %s differ in size\n", argv[2], argv[3]);
      return 1;
    }
    long different = 0;
    const long n = static_cast<long>(a.w) * a.h;
    for (long i = 0; i < n; ++i)
      different += differs(a.pixel(static_cast<int>(i)), b.pixel(static_cast<int>(i)));
    const double f = static_cast<double>(different) / n;
    std::printf("%s and %s: %.2f%% of the pixels differ\n", argv[2], argv[3], 100 * f);
    return f >= std::atof(argv[4]) ? 0 : 1;
  }
  std::fprintf(stderr, "usage: image_check coverage IMAGE MIN MAX | image_check differ A B MIN\n");
  return 2;
}
