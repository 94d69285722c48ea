/* curray io: MP4 videos of PNG frames with FFmpeg's libraries (video.h). */
#include "video.h"

#include "module.h"

/* What curray_video.so gives the program (module.h). */
typedef struct cr_video_module {
    cr_module_header head;
    int (*from_pngs)(const char *dir, const char *prefix, int n, int fps, const char *name,
                     int *padded, atomic_int *cancel, cr_err *err);
} cr_video_module;

#define CR_VIDEO_MODULE_FILE "curray_video" CURRAY_MODULE_SUFFIX
#define CR_VIDEO_MODULE_NEEDS                                                                  \
    "FFmpeg's libraries libavformat, libavcodec, libswscale and libavutil (Debian: "           \
    "apt-get install ffmpeg, or the -dev packages of tools/install-deps.sh)"

#if defined(CURRAY_VIDEO_MODULE_HOST)

static const cr_video_module *cr_video_module_get(cr_err *err)
{
    return cr_module_load(CR_VIDEO_MODULE_FILE, "curray_video_module", "video module",
                          CR_VIDEO_MODULE_NEEDS, err);
}

int cr_video_available(cr_err *err)
{
    cr_err e;
    if (cr_video_module_get(&e))
        return 1;
    cr_err_set(err, "-t v: %s", e.msg);
    return 0;
}

int cr_video_from_pngs(const char *dir, const char *prefix, int n, int fps, const char *name,
                       int *padded, atomic_int *cancel, cr_err *err)
{
    const cr_video_module *m = cr_video_module_get(err);
    return m ? m->from_pngs(dir, prefix, n, fps, name, padded, cancel, err) : -1;
}

#elif !defined(CURRAY_HAVE_FFMPEG)

int cr_video_available(cr_err *err)
{
    cr_err_set(err, "-t v: %s", CR_VIDEO_UNAVAILABLE);
    return 0;
}

int cr_video_from_pngs(const char *dir, const char *prefix, int n, int fps, const char *name,
                       int *padded, atomic_int *cancel, cr_err *err)
{
    (void)dir, (void)prefix, (void)n, (void)fps, (void)name, (void)padded, (void)cancel;
    return cr_err_set(err, "%s", CR_VIDEO_UNAVAILABLE);
}

#else

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>

#include "../base/atomic.h"
#include "../base/fsutil.h"
#include "../base/png_io.h"

int cr_video_available(cr_err *err)
{
    (void)err;
    return 1;
}

/* FFmpeg 7 (libavformat 61) made the write callback's buffer const. */
#if LIBAVFORMAT_VERSION_MAJOR >= 61
#define CR_AVIO_BUF const uint8_t
#else
#define CR_AVIO_BUF uint8_t
#endif

/* libavformat writes through these into the cr_atomic temporary file. */
static int cr_avio_write(void *opaque, CR_AVIO_BUF *buf, int n)
{
    return fwrite(buf, 1, (size_t)n, (FILE *)opaque) == (size_t)n ? n : AVERROR(EIO);
}

static int64_t cr_avio_seek(void *opaque, int64_t off, int whence)
{
    FILE *fp = opaque;
    if (whence & AVSEEK_SIZE) {
        long here = ftell(fp), size;
        if (here < 0 || fseek(fp, 0, SEEK_END) != 0)
            return AVERROR(EIO);
        size = ftell(fp);
        fseek(fp, here, SEEK_SET);
        return size;
    }
    if (fseek(fp, (long)off, whence & ~AVSEEK_FORCE) != 0)
        return AVERROR(EIO);
    return ftell(fp);
}

typedef struct cr_video {
    cr_atomic file;
    int file_open;
    AVFormatContext *fmt;
    AVIOContext *io;
    AVCodecContext *enc;
    AVStream *st;
    AVFrame *frame;
    AVPacket *pkt;
    struct SwsContext *sws;
    uint8_t *pad; /* the frame padded to even size (W x H x 3), then CR_VIDEO_SRC_SLACK bytes */
    int w, h, W, H;
} cr_video;

/* sws_scale's SIMD readers load up to 32 bytes past the end of an RGB24
 * source (libswscale 6, x86: measured with a guard page after the image), so
 * the source buffer carries FFmpeg's input padding beyond the image. */
#define CR_VIDEO_SRC_SLACK AV_INPUT_BUFFER_PADDING_SIZE

static int cr_av_fail(cr_err *err, const char *path, const char *what, int code)
{
    char msg[AV_ERROR_MAX_STRING_SIZE] = "";
    av_strerror(code, msg, sizeof msg);
    return cr_err_set(err, "writing %s: %s: %s", path, what, msg);
}

/* Send frame (NULL: flush) and write every packet the encoder returns. */
static int cr_video_encode(cr_video *v, AVFrame *frame, cr_err *err)
{
    int rc = avcodec_send_frame(v->enc, frame);
    if (rc < 0)
        return cr_av_fail(err, v->file.path, "encoding", rc);
    for (;;) {
        rc = avcodec_receive_packet(v->enc, v->pkt);
        if (rc == AVERROR(EAGAIN) || rc == AVERROR_EOF)
            return 0;
        if (rc < 0)
            return cr_av_fail(err, v->file.path, "encoding", rc);
        av_packet_rescale_ts(v->pkt, v->enc->time_base, v->st->time_base);
        v->pkt->stream_index = v->st->index;
        rc = av_interleaved_write_frame(v->fmt, v->pkt);
        if (rc < 0)
            return cr_av_fail(err, v->file.path, "writing a packet", rc);
    }
}

static int cr_video_open(cr_video *v, const char *path, int w, int h, int fps, cr_err *err)
{
    const AVCodec *codec = avcodec_find_encoder(AV_CODEC_ID_H264);
    unsigned char *buf;
    int rc;
    v->w = w;
    v->h = h;
    v->W = w + (w & 1);
    v->H = h + (h & 1);
    if (!codec)
        return cr_err_set(err, "writing %s: this FFmpeg has no H.264 encoder (Debian's libavcodec "
                               "has libx264)",
                          path);
    if (cr_atomic_open(&v->file, path, err))
        return -1;
    v->file_open = 1;
    rc = avformat_alloc_output_context2(&v->fmt, NULL, "mp4", NULL);
    if (rc < 0 || !v->fmt)
        return cr_av_fail(err, path, "no MP4 muxer", rc);
    buf = av_malloc(1 << 16);
    v->io = buf ? avio_alloc_context(buf, 1 << 16, 1, v->file.fp, NULL, cr_avio_write,
                                     cr_avio_seek)
                : NULL;
    if (!v->io) {
        av_free(buf);
        return cr_err_set(err, "writing %s: out of memory", path);
    }
    v->fmt->pb = v->io;
    v->fmt->flags |= AVFMT_FLAG_CUSTOM_IO;
    v->st = avformat_new_stream(v->fmt, NULL);
    v->enc = avcodec_alloc_context3(codec);
    v->frame = av_frame_alloc();
    v->pkt = av_packet_alloc();
    v->pad = av_mallocz((size_t)v->W * (size_t)v->H * 3 + CR_VIDEO_SRC_SLACK);
    if (!v->st || !v->enc || !v->frame || !v->pkt || !v->pad)
        return cr_err_set(err, "writing %s: out of memory", path);
    v->enc->width = v->W;
    v->enc->height = v->H;
    v->enc->pix_fmt = AV_PIX_FMT_YUV420P;
    v->enc->time_base = (AVRational){1, fps};
    v->enc->framerate = (AVRational){fps, 1};
    v->enc->gop_size = fps;
    v->enc->color_range = AVCOL_RANGE_MPEG;
    v->enc->colorspace = AVCOL_SPC_BT709;
    v->enc->color_primaries = AVCOL_PRI_BT709;
    v->enc->color_trc = AVCOL_TRC_IEC61966_2_1; /* sRGB, as the PNG frames */
    if (v->fmt->oformat->flags & AVFMT_GLOBALHEADER)
        v->enc->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    /* libx264: constant quality 18 (visually lossless for such images) */
    av_opt_set(v->enc->priv_data, "crf", "18", 0);
    av_opt_set(v->enc->priv_data, "preset", "medium", 0);
    rc = avcodec_open2(v->enc, codec, NULL);
    if (rc < 0)
        return cr_av_fail(err, path, "opening the H.264 encoder", rc);
    rc = avcodec_parameters_from_context(v->st->codecpar, v->enc);
    if (rc < 0)
        return cr_av_fail(err, path, "stream parameters", rc);
    v->st->time_base = v->enc->time_base;
    v->st->avg_frame_rate = v->enc->framerate;
    v->frame->format = AV_PIX_FMT_YUV420P;
    v->frame->width = v->W;
    v->frame->height = v->H;
    rc = av_frame_get_buffer(v->frame, 0);
    if (rc < 0)
        return cr_av_fail(err, path, "frame buffer", rc);
    v->sws = sws_getContext(v->W, v->H, AV_PIX_FMT_RGB24, v->W, v->H, AV_PIX_FMT_YUV420P,
                            SWS_BICUBIC | SWS_ACCURATE_RND, NULL, NULL,
                            NULL);
    if (!v->sws)
        return cr_err_set(err, "writing %s: cannot set up the RGB to YUV conversion", path);
    {
        /* BT.709 coefficients, limited range, matching the stream's tags */
        const int *coef = sws_getCoefficients(SWS_CS_ITU709);
        sws_setColorspaceDetails(v->sws, coef, 1, coef, 0, 0, 1 << 16, 1 << 16);
    }
    rc = avformat_write_header(v->fmt, NULL);
    if (rc < 0)
        return cr_av_fail(err, path, "MP4 header", rc);
    return 0;
}

/* Frame k (rgb, w x h) into the video, padded to W x H by repeating the last
 * column and row. */
static int cr_video_add(cr_video *v, const uint8_t *rgb, int64_t k, cr_err *err)
{
    const uint8_t *src[1];
    int stride[1] = {3 * v->W};
    int y, rc;
    for (y = 0; y < v->H; y++) {
        const uint8_t *row = rgb + (size_t)(y < v->h ? y : v->h - 1) * (size_t)v->w * 3;
        uint8_t *dst = v->pad + (size_t)y * (size_t)v->W * 3;
        memcpy(dst, row, (size_t)v->w * 3);
        if (v->W > v->w)
            memcpy(dst + (size_t)v->w * 3, row + (size_t)(v->w - 1) * 3, 3);
    }
    rc = av_frame_make_writable(v->frame);
    if (rc < 0)
        return cr_av_fail(err, v->file.path, "frame buffer", rc);
    src[0] = v->pad;
    sws_scale(v->sws, src, stride, 0, v->H, v->frame->data, v->frame->linesize);
    v->frame->pts = k;
    return cr_video_encode(v, v->frame, err);
}

/* Finish (when ok) or abandon the video; frees everything. */
static int cr_video_close(cr_video *v, int ok, cr_err *err)
{
    int rc = ok ? 0 : -1;
    if (ok) {
        int r = av_write_trailer(v->fmt);
        if (r < 0)
            rc = cr_av_fail(err, v->file.path, "MP4 trailer", r);
        else
            avio_flush(v->io);
    }
    if (v->io) {
        av_freep(&v->io->buffer);
        avio_context_free(&v->io);
    }
    avformat_free_context(v->fmt);
    avcodec_free_context(&v->enc);
    av_frame_free(&v->frame);
    av_packet_free(&v->pkt);
    sws_freeContext(v->sws);
    av_free(v->pad);
    if (v->file_open) {
        if (rc == 0)
            rc = cr_atomic_commit(&v->file, err);
        else
            cr_atomic_abort(&v->file);
    }
    return rc;
}

int cr_video_from_pngs(const char *dir, const char *prefix, int n, int fps, const char *name,
                       int *padded, atomic_int *cancel, cr_err *err)
{
    char path[4096], frame[4096], fname[64];
    cr_video v;
    int k, rc = 0;
    memset(&v, 0, sizeof v);
    if (padded)
        *padded = 0;
    if (n < 1 || fps < 1 || fps > CR_VIDEO_MAX_FPS)
        return cr_err_set(err, "video %s: %d frames at %d fps", name, n, fps);
    if (cr_path_join(path, sizeof path, dir, name) != 0)
        return cr_err_set(err, "output folder name too long: '%s'", dir);
    av_log_set_level(AV_LOG_ERROR);
    for (k = 0; k < n && rc == 0; k++) {
        uint8_t *rgb = NULL;
        int w, h;
        if (cancel && atomic_load_explicit(cancel, memory_order_relaxed) > 0) {
            rc = cr_err_set(err, "interrupted");
            break;
        }
        snprintf(fname, sizeof fname, "%s_%d.png", prefix, k);
        if (cr_path_join(frame, sizeof frame, dir, fname) != 0) {
            rc = cr_err_set(err, "output folder name too long: '%s'", dir);
            break;
        }
        if (cr_png_read(frame, 0, &rgb, &w, &h, err)) {
            rc = -1;
            break;
        }
        if (k == 0) {
            rc = cr_video_open(&v, path, w, h, fps, err);
            if (padded)
                *padded = (w | h) & 1;
        } else if (w != v.w || h != v.h) {
            rc = cr_err_set(err, "writing %s: %s is %dx%d, frame 0 is %dx%d", path, frame, w, h,
                            v.w, v.h);
        }
        if (rc == 0)
            rc = cr_video_add(&v, rgb, k, err);
        free(rgb);
    }
    if (rc == 0)
        rc = cr_video_encode(&v, NULL, err);
    return cr_video_close(&v, rc == 0, err);
}

#if defined(CURRAY_VIDEO_MODULE)
/* The entry of curray_video.so. */
CR_MODULE_EXPORT const cr_video_module *curray_video_module(void);
CR_MODULE_EXPORT const cr_video_module *curray_video_module(void)
{
    static const cr_video_module m = {{CURRAY_VERSION, CR_MODULE_LAYOUT}, cr_video_from_pngs};
    return &m;
}
#endif

#endif
