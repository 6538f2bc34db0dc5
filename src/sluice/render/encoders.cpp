#include "sluice/render/encoders.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <gif_lib.h>
#include <png.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <vector>

#include "sluice/io/atomic_file.hpp"

extern char** environ;

namespace sluice::render {

// ---------------------------------------------------------------------------------------------
// PNG

namespace {

void png_append(png_structp png, png_bytep data, png_size_t length) {
  static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<const char*>(data), length);
}
void png_no_flush(png_structp) {}
void png_on_error(png_structp png, png_const_charp message) {
  char* buffer = static_cast<char*>(png_get_error_ptr(png));
  std::snprintf(buffer, 256, "%s", message);
  png_longjmp(png, 1);
}
void png_on_warning(png_structp, png_const_charp) {}

// C style on purpose: no object with a destructor lives across setjmp/longjmp.
bool encode_png_c(const std::uint8_t* pixels, int width, int height, const png_color* palette, std::string* out,
                  char* error) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, error, png_on_error, png_on_warning);
  if (png == nullptr) return false;
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, out, png_append, png_no_flush);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
               PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_PLTE(png, info, palette, 256);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);  // the advice for palette images
  png_write_info(png, info);
  for (int y = 0; y < height; ++y) png_write_row(png, pixels + static_cast<std::ptrdiff_t>(y) * width);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

// PNG bytes of `image` (8-bit palette PNG).
std::string encode_png(const IndexedImage& image, const Palette& palette) {
  png_color colours[256];
  for (int i = 0; i < 256; ++i) colours[i] = {palette.colours[i].r, palette.colours[i].g, palette.colours[i].b};
  std::string out;
  char error[256] = "out of memory";
  if (!encode_png_c(image.pixels.data(), image.width, image.height, colours, &out, error))
    throw IoError(fmt::format("libpng could not encode a {}x{} picture: {}", image.width, image.height, error));
  return out;
}

}  // namespace

void write_png(const std::filesystem::path& path, const IndexedImage& image, const Palette& palette) {
  write_file_atomic(path, encode_png(image, palette));
}

// ---------------------------------------------------------------------------------------------
// GIF

namespace {

class GifWriter final : public AnimationWriter {
 public:
  GifWriter(const std::filesystem::path& path, int width, int height, const Palette& palette, int delay)
      : path_(path), file_(path), width_(width), height_(height), delay_(delay), row_(static_cast<std::size_t>(width)) {
    int error = 0;
    gif_ = EGifOpen(this, &GifWriter::output, &error);
    if (gif_ == nullptr) fail("giflib could not start the file", error);
    EGifSetGifVersion(gif_, true);  // GIF89a: frame delays and looping
    GifColorType colours[256];
    for (int i = 0; i < 256; ++i) colours[i] = {palette.colours[i].r, palette.colours[i].g, palette.colours[i].b};
    ColorMapObject* map = GifMakeMapObject(256, colours);
    if (map == nullptr) fail("giflib: out of memory", D_GIF_ERR_NOT_ENOUGH_MEM);
    const int status = EGifPutScreenDesc(gif_, width, height, 8, Palette::white, map);
    GifFreeMapObject(map);
    check(status, "writing the screen descriptor");
    // NETSCAPE2.0 application extension: loop forever.
    static const unsigned char netscape[] = "NETSCAPE2.0";
    unsigned char loop[3] = {1, 0, 0};
    check(EGifPutExtensionLeader(gif_, APPLICATION_EXT_FUNC_CODE), "writing the loop extension");
    check(EGifPutExtensionBlock(gif_, 11, netscape), "writing the loop extension");
    check(EGifPutExtensionBlock(gif_, 3, loop), "writing the loop extension");
    check(EGifPutExtensionTrailer(gif_), "writing the loop extension");
  }

  ~GifWriter() override {
    if (gif_ != nullptr) {
      int error = 0;
      EGifCloseFile(gif_, &error);  // the temporary file is removed by file_
    }
  }

  void add(const IndexedImage& frame) override {
    if (frame.width != width_ || frame.height != height_)
      throw std::logic_error("GifWriter: frames must all have the animation's size");
    GraphicsControlBlock gcb{};
    gcb.DisposalMode = DISPOSE_DO_NOT;
    gcb.UserInputFlag = false;
    gcb.DelayTime = delay_;
    gcb.TransparentColor = NO_TRANSPARENT_COLOR;
    // After the first frame, only the rectangle of changed pixels is stored, its unchanged pixels
    // transparent over the previous frame (kept: DISPOSE_DO_NOT): the same pictures, a smaller file.
    Rect r{0, 0, width_, height_};
    const bool diff = !previous_.pixels.empty();
    if (diff) {
      r = {width_, height_, 0, 0};
      for (int y = 0; y < height_; ++y) {
        const std::uint8_t* a = &frame.pixels[static_cast<std::size_t>(y) * width_];
        const std::uint8_t* b = &previous_.pixels[static_cast<std::size_t>(y) * width_];
        if (std::memcmp(a, b, static_cast<std::size_t>(width_)) == 0) continue;
        int x0 = 0, x1 = width_;
        while (a[x0] == b[x0]) ++x0;
        while (a[x1 - 1] == b[x1 - 1]) --x1;
        r = {std::min(r.x0, x0), std::min(r.y0, y), std::max(r.x1, x1), y + 1};
      }
      if (r.x0 >= r.x1) r = {0, 0, 1, 1};  // nothing changed: one transparent pixel
      gcb.TransparentColor = Palette::transparent;
    }
    GifByteType extension[4];
    const std::size_t n = EGifGCBToExtension(&gcb, extension);
    check(EGifPutExtension(gif_, GRAPHICS_EXT_FUNC_CODE, static_cast<int>(n), extension), "writing a frame delay");
    check(EGifPutImageDesc(gif_, r.x0, r.y0, r.width(), r.height(), false, nullptr), "writing a frame");
    for (int y = r.y0; y < r.y1; ++y) {
      for (int x = r.x0; x < r.x1; ++x) {
        const std::uint8_t p = frame.at(x, y);
        if (p == Palette::transparent) throw std::logic_error("GifWriter: a picture uses the reserved palette entry");
        row_[static_cast<std::size_t>(x - r.x0)] = diff && p == previous_.at(x, y) ? Palette::transparent : p;
      }
      check(EGifPutLine(gif_, row_.data(), r.width()), "writing a frame");
    }
    previous_ = frame;
  }

  void finish() override {
    int error = 0;
    GifFileType* gif = gif_;
    gif_ = nullptr;
    if (EGifCloseFile(gif, &error) != GIF_OK) fail("finishing the file", error);
    file_.commit();
  }

 private:
  static int output(GifFileType* gif, const GifByteType* data, int length) {
    auto* self = static_cast<GifWriter*>(gif->UserData);
    try {
      self->file_.write(data, static_cast<std::size_t>(length));
      return length;
    } catch (...) {  // no exception may cross giflib's C frames
      self->write_error_ = std::current_exception();
      return 0;
    }
  }

  void check(int status, const char* what) {
    if (status != GIF_OK) fail(what, gif_ != nullptr ? gif_->Error : 0);
  }

  [[noreturn]] void fail(const char* what, int error) {
    if (write_error_) std::rethrow_exception(write_error_);
    const char* reason = GifErrorString(error);
    throw IoError(fmt::format("{}: GIF {}: {}", path_.string(), what, reason != nullptr ? reason : "unknown error"));
  }

  std::filesystem::path path_;
  AtomicFile file_;
  GifFileType* gif_ = nullptr;
  int width_, height_, delay_;
  std::vector<GifPixelType> row_;
  IndexedImage previous_;
  std::exception_ptr write_error_;
};

}  // namespace

std::unique_ptr<AnimationWriter> open_gif(const std::filesystem::path& path, int width, int height,
                                          const Palette& palette, int delay_centiseconds) {
  return std::make_unique<GifWriter>(path, width, height, palette, delay_centiseconds);
}

// ---------------------------------------------------------------------------------------------
// MP4 through ffmpeg

std::optional<std::filesystem::path> find_program(std::string_view name) {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return std::nullopt;
  std::string_view rest = path;
  while (true) {
    const auto colon = rest.find(':');
    const std::string_view dir = rest.substr(0, colon);
    const std::filesystem::path candidate = std::filesystem::path(dir.empty() ? "." : std::string(dir)) / name;
    if (::access(candidate.c_str(), X_OK) == 0) {
      std::error_code ec;
      if (std::filesystem::is_regular_file(candidate, ec)) return candidate;
    }
    if (colon == std::string_view::npos) break;
    rest.remove_prefix(colon + 1);
  }
  return std::nullopt;
}

void require_ffmpeg() {
  if (!find_program("ffmpeg"))
    throw IoError("MP4 needs the ffmpeg program, which is not installed (not found on PATH): install it "
                  "(apt-get install ffmpeg) or render a GIF (--format gif)");
}

namespace {

class FfmpegWriter final : public AnimationWriter {
 public:
  FfmpegWriter(const std::filesystem::path& path, int width, int height, const Palette& palette, int fps)
      : path_(path), temp_(path.string() + ".part"), palette_(palette), width_(width), height_(height) {
    require_ffmpeg();
    const auto ffmpeg = find_program("ffmpeg");
    if (width % 2 != 0 || height % 2 != 0)
      throw std::logic_error("FfmpegWriter: H.264 (yuv420p) needs an even width and height");
    const std::vector<std::string> args = {ffmpeg->string(), "-hide_banner", "-loglevel", "error", "-y",
                                           "-f", "rawvideo", "-pixel_format", "rgb24",
                                           "-video_size", fmt::format("{}x{}", width, height),
                                           "-framerate", std::to_string(fps), "-i", "pipe:0", "-an",
                                           "-c:v", "libx264", "-pix_fmt", "yuv420p", "-crf", "18",
                                           "-movflags", "+faststart", "-f", "mp4", temp_.string()};
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);

    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) throw IoError(fmt::format("cannot start ffmpeg: pipe: {}", std::strerror(errno)));
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[0], STDIN_FILENO);  // dup2 clears O_CLOEXEC
    const int rc = posix_spawn(&pid_, ffmpeg->c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(fds[0]);
    if (rc != 0) {
      ::close(fds[1]);
      throw IoError(fmt::format("cannot start {}: {}", ffmpeg->string(), std::strerror(rc)));
    }
    fd_ = fds[1];
    previous_sigpipe_ = std::signal(SIGPIPE, SIG_IGN);  // a dead ffmpeg is an error, not a signal
  }

  ~FfmpegWriter() override {
    if (fd_ >= 0) ::close(fd_);
    if (pid_ > 0) {
      int status = 0;
      ::waitpid(pid_, &status, 0);
    }
    std::error_code ec;
    if (!finished_) std::filesystem::remove(temp_, ec);
    std::signal(SIGPIPE, previous_sigpipe_);
  }

  void add(const IndexedImage& frame) override {
    if (frame.width != width_ || frame.height != height_)
      throw std::logic_error("FfmpegWriter: frames must all have the animation's size");
    const auto rgb = to_rgb(frame, palette_);
    std::size_t done = 0;
    while (done < rgb.size()) {
      const ssize_t n = ::write(fd_, rgb.data() + done, rgb.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        const int err = errno;
        wait_for_ffmpeg();
        throw IoError(fmt::format("{}: ffmpeg stopped taking frames ({}); its messages are above", path_.string(),
                                  std::strerror(err)));
      }
      done += static_cast<std::size_t>(n);
    }
  }

  void finish() override {
    if (const int status = wait_for_ffmpeg(); status != 0)
      throw IoError(fmt::format("{}: ffmpeg failed ({}); its messages are above", path_.string(),
                                status > 0 ? fmt::format("exit status {}", status) : "killed by a signal"));
    std::error_code ec;
    std::filesystem::rename(temp_, path_, ec);
    if (ec) throw IoError(fmt::format("{}: cannot rename {} to it: {}", path_.string(), temp_.string(), ec.message()));
    finished_ = true;
  }

 private:
  // Closes the pipe and waits: the exit status, or -1 if ffmpeg was killed.
  int wait_for_ffmpeg() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  std::filesystem::path path_, temp_;
  Palette palette_;
  int width_, height_;
  pid_t pid_ = -1;
  int fd_ = -1;
  bool finished_ = false;
  void (*previous_sigpipe_)(int) = SIG_DFL;
};

}  // namespace

std::unique_ptr<AnimationWriter> open_mp4(const std::filesystem::path& path, int width, int height,
                                          const Palette& palette, int fps) {
  return std::make_unique<FfmpegWriter>(path, width, height, palette, fps);
}

}  // namespace sluice::render
