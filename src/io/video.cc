#include "io/video.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <mutex>
#include <system_error>

#include "core/errors.h"

namespace hribench::io {
namespace {

// x264's presets, fastest first (x264 --help).
constexpr std::array<std::string_view, 10> kPresets = {
    "ultrafast", "superfast", "veryfast", "faster",   "fast",
    "medium",    "slow",      "slower",   "veryslow", "placebo"};

std::string av_error(int code) {
  std::array<char, AV_ERROR_MAX_STRING_SIZE> text{};
  av_strerror(code, text.data(), text.size());
  return text.data();
}

// libav prints encoder statistics at info level on stderr; only its errors are worth showing.
void quiet_libav() {
  static std::once_flag once;
  std::call_once(once, [] { av_log_set_level(AV_LOG_ERROR); });
}

std::string preset_list() {
  std::string list;
  for (auto preset : kPresets) list += (list.empty() ? "" : ", ") + std::string(preset);
  return list;
}

}  // namespace

struct VideoWriter::Impl {
  std::filesystem::path path;
  std::filesystem::path temporary;
  int width = 0;
  int height = 0;
  VideoSettings settings;
  int64_t frames = 0;
  bool finished = false;

  AVFormatContext* format = nullptr;
  AVCodecContext* codec = nullptr;
  AVStream* stream = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  SwsContext* scaler = nullptr;

  ~Impl() {
    sws_freeContext(scaler);
    av_packet_free(&packet);
    av_frame_free(&frame);
    avcodec_free_context(&codec);
    if (format != nullptr) {
      if (format->pb != nullptr) avio_closep(&format->pb);
      avformat_free_context(format);
    }
    if (!finished && !temporary.empty()) {
      std::error_code ignored;
      std::filesystem::remove(temporary, ignored);
    }
  }

  [[noreturn]] void fail(std::string_view what, int code) const {
    throw core::InputError::Message(path.string(),
                                    fmt::format("cannot write the video: {}: {}", what,
                                                av_error(code)));
  }

  // Sends `input` (null: flush) and writes every packet the encoder returns.
  void encode(const AVFrame* input) {
    int status = avcodec_send_frame(codec, input);
    if (status < 0) fail("encoding a frame", status);
    while (true) {
      status = avcodec_receive_packet(codec, packet);
      if (status == AVERROR(EAGAIN) || status == AVERROR_EOF) return;
      if (status < 0) fail("encoding a frame", status);
      av_packet_rescale_ts(packet, codec->time_base, stream->time_base);
      packet->stream_index = stream->index;
      status = av_interleaved_write_frame(format, packet);
      if (status < 0) fail("writing a packet", status);
    }
  }
};

VideoWriter::VideoWriter(std::filesystem::path path, int width, int height,
                         VideoSettings settings)
    : impl_(std::make_unique<Impl>()) {
  Impl& v = *impl_;
  v.path = std::move(path);
  v.width = width;
  v.height = height;
  v.settings = settings;
  const std::string where = v.path.string();
  if (width <= 0 || height <= 0 || width % 2 != 0 || height % 2 != 0)
    throw core::InputError(where, "an even, positive width and height (yuv420p halves them)",
                           fmt::format("{}x{}", width, height));
  if (settings.fps < 1)
    throw core::InputError(where + ": fps", "a whole number >= 1", std::to_string(settings.fps));
  if (settings.crf < 0 || settings.crf > 51)
    throw core::InputError(where + ": crf", "0..51", std::to_string(settings.crf));
  if (settings.gop < 1)
    throw core::InputError(where + ": gop", "a whole number >= 1", std::to_string(settings.gop));
  if (std::find(kPresets.begin(), kPresets.end(), settings.preset) == kPresets.end())
    throw core::InputError(where + ": preset", "one of " + preset_list(), settings.preset);

  quiet_libav();
  const AVCodec* encoder = avcodec_find_encoder_by_name("libx264");
  if (encoder == nullptr)
    throw core::InputError::Message(where, "libavcodec has no libx264 encoder (install ffmpeg's "
                                           "libavcodec with x264: scripts/install-deps.sh)");
  v.temporary = v.path;
  v.temporary += ".tmp";
  int status = avformat_alloc_output_context2(&v.format, nullptr, "mp4", nullptr);
  if (status < 0 || v.format == nullptr) v.fail("making the mp4 muxer", status);
  v.format->flags |= AVFMT_FLAG_BITEXACT;  // no library version strings: same frames, same bytes

  v.codec = avcodec_alloc_context3(encoder);
  if (v.codec == nullptr) v.fail("making the encoder", AVERROR(ENOMEM));
  v.codec->width = width;
  v.codec->height = height;
  v.codec->time_base = AVRational{1, settings.fps};
  v.codec->framerate = AVRational{settings.fps, 1};
  v.codec->pix_fmt = AV_PIX_FMT_YUV420P;
  v.codec->gop_size = settings.gop;
  v.codec->max_b_frames = 0;  // decode order = display order: frame i is packet i
  v.codec->thread_count = 1;  // one encoder per worker thread; workers give the parallelism
  v.codec->color_range = AVCOL_RANGE_MPEG;  // what swscale's RGB -> yuv420p produces (BT.601)
  v.codec->colorspace = AVCOL_SPC_SMPTE170M;
  v.codec->color_primaries = AVCOL_PRI_SMPTE170M;
  v.codec->color_trc = AVCOL_TRC_SMPTE170M;
  v.codec->flags |= AV_CODEC_FLAG_BITEXACT;
  if (v.format->oformat->flags & AVFMT_GLOBALHEADER) v.codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  av_opt_set(v.codec->priv_data, "preset", settings.preset.c_str(), 0);
  av_opt_set(v.codec->priv_data, "crf", std::to_string(settings.crf).c_str(), 0);
  status = avcodec_open2(v.codec, encoder, nullptr);
  if (status < 0) v.fail("opening libx264", status);

  v.stream = avformat_new_stream(v.format, nullptr);
  if (v.stream == nullptr) v.fail("adding the video stream", AVERROR(ENOMEM));
  v.stream->time_base = v.codec->time_base;
  v.stream->avg_frame_rate = v.codec->framerate;
  status = avcodec_parameters_from_context(v.stream->codecpar, v.codec);
  if (status < 0) v.fail("describing the video stream", status);

  status = avio_open(&v.format->pb, v.temporary.c_str(), AVIO_FLAG_WRITE);
  if (status < 0) v.fail("opening " + v.temporary.string(), status);
  status = avformat_write_header(v.format, nullptr);
  if (status < 0) v.fail("writing the mp4 header", status);

  v.frame = av_frame_alloc();
  v.packet = av_packet_alloc();
  if (v.frame == nullptr || v.packet == nullptr) v.fail("allocating a frame", AVERROR(ENOMEM));
  v.frame->format = AV_PIX_FMT_YUV420P;
  v.frame->width = width;
  v.frame->height = height;
  v.frame->color_range = v.codec->color_range;
  v.frame->colorspace = v.codec->colorspace;
  status = av_frame_get_buffer(v.frame, 0);
  if (status < 0) v.fail("allocating a frame", status);
  v.scaler = sws_getContext(width, height, AV_PIX_FMT_RGB24, width, height, AV_PIX_FMT_YUV420P,
                            SWS_BILINEAR | SWS_ACCURATE_RND | SWS_BITEXACT, nullptr, nullptr,
                            nullptr);
  if (v.scaler == nullptr) v.fail("making the RGB to yuv420p converter", AVERROR(EINVAL));
}

VideoWriter::~VideoWriter() = default;

int VideoWriter::width() const { return impl_->width; }
int VideoWriter::height() const { return impl_->height; }
const VideoSettings& VideoWriter::settings() const { return impl_->settings; }
const std::filesystem::path& VideoWriter::path() const { return impl_->path; }
int64_t VideoWriter::frames() const { return impl_->frames; }

void VideoWriter::add(const render::Image& image) {
  Impl& v = *impl_;
  HRIB_CHECK(!v.finished);
  if (image.width != v.width || image.height != v.height)
    throw core::InputError(v.path.string() + ": frame " + std::to_string(v.frames),
                           fmt::format("a {}x{} RGB image", v.width, v.height),
                           fmt::format("{}x{}", image.width, image.height));
  int status = av_frame_make_writable(v.frame);
  if (status < 0) v.fail("allocating a frame", status);
  const uint8_t* source[1] = {image.rgb.data()};
  const int source_stride[1] = {3 * image.width};
  sws_scale(v.scaler, source, source_stride, 0, v.height, v.frame->data, v.frame->linesize);
  v.frame->pts = v.frames;
  v.encode(v.frame);
  ++v.frames;
}

void VideoWriter::finish() {
  Impl& v = *impl_;
  HRIB_CHECK(!v.finished);
  if (v.frames == 0)
    throw core::InputError(v.path.string(), "at least one frame", "none");
  v.encode(nullptr);
  int status = av_write_trailer(v.format);
  if (status < 0) v.fail("writing the mp4 index", status);
  status = avio_closep(&v.format->pb);
  if (status < 0) v.fail("closing the file", status);
  std::error_code error;
  std::filesystem::rename(v.temporary, v.path, error);
  if (error)
    throw core::InputError::Message(v.path.string(),
                                    "cannot write the video: " + error.message());
  v.finished = true;
}

std::string video_encoder_version() {
  return fmt::format("libavcodec {}.{}.{} libx264", LIBAVCODEC_VERSION_MAJOR,
                     LIBAVCODEC_VERSION_MINOR, LIBAVCODEC_VERSION_MICRO);
}

}  // namespace hribench::io
