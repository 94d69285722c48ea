/* video_probe: read an MP4 with libavformat/libavcodec and report what
 * tests/cli/test_video.sh checks:
 *
 *   video_probe VIDEO.mp4 FRAME0.png
 *   -> "codec h264 pix_fmt yuv420p frames N size WxH fps A/B psnr P"
 *
 * frames: decoded pictures; size: the coded picture; fps: the stream's
 * average frame rate; psnr: of the first picture, converted back to RGB
 * (BT.709, limited range, as video.c writes it) and cropped to the PNG's
 * size, against the PNG (8-bit RGB, all three channels), in dB. Exit status
 * 1 when the file cannot be read or decoded. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>

#include "base/png_io.h"

static double psnr_rgb(const AVFrame *f, const uint8_t *png, int w, int h)
{
    uint8_t *rgb = malloc((size_t)f->width * (size_t)f->height * 3);
    uint8_t *dst[1] = {rgb};
    int stride[1] = {3 * f->width};
    struct SwsContext *sws = sws_getContext(f->width, f->height, f->format, f->width, f->height,
                                            AV_PIX_FMT_RGB24,
                                            SWS_BICUBIC | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT,
                                            NULL, NULL, NULL);
    const int *coef = sws_getCoefficients(SWS_CS_ITU709);
    double se = 0.0;
    if (!rgb || !sws)
        return -1.0;
    sws_setColorspaceDetails(sws, coef, 0, coef, 1, 0, 1 << 16, 1 << 16);
    sws_scale(sws, (const uint8_t *const *)f->data, f->linesize, 0, f->height, dst, stride);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < 3 * w; x++) {
            double d = (double)rgb[(size_t)y * (size_t)stride[0] + (size_t)x] -
                       (double)png[((size_t)y * (size_t)w) * 3 + (size_t)x];
            se += d * d;
        }
    sws_freeContext(sws);
    free(rgb);
    se /= 3.0 * w * h;
    return se > 0.0 ? 10.0 * log10(255.0 * 255.0 / se) : 99.0;
}

/* PSNR of the luma plane against the PNG's BT.709 limited-range luma
 * Y = 16 + 219 (0.2126 R + 0.7152 G + 0.0722 B) / 255, in dB. */
static double psnr_y(const AVFrame *f, const uint8_t *png, int w, int h)
{
    double se = 0.0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const uint8_t *p = png + ((size_t)y * (size_t)w + (size_t)x) * 3;
            double ref = 16.0 + 219.0 * (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]) / 255.0;
            double d = (double)f->data[0][(size_t)y * (size_t)f->linesize[0] + (size_t)x] - ref;
            se += d * d;
        }
    se /= (double)w * h;
    return se > 0.0 ? 10.0 * log10(255.0 * 255.0 / se) : 99.0;
}

int main(int argc, char **argv)
{
    AVFormatContext *fmt = NULL;
    AVCodecContext *dec = NULL;
    AVPacket *pkt = av_packet_alloc();
    AVFrame *frame = av_frame_alloc();
    const AVCodec *codec;
    uint8_t *png = NULL;
    int w, h, si, frames = 0, rc;
    double psnr = -1.0, psnr_luma = -1.0;
    cr_err err;
    if (argc != 3) {
        fprintf(stderr, "usage: video_probe VIDEO.mp4 FRAME0.png\n");
        return 2;
    }
    if (cr_png_read(argv[2], 0, &png, &w, &h, &err)) {
        fprintf(stderr, "video_probe: %s\n", err.msg);
        return 1;
    }
    if (avformat_open_input(&fmt, argv[1], NULL, NULL) < 0 ||
        avformat_find_stream_info(fmt, NULL) < 0) {
        fprintf(stderr, "video_probe: cannot read %s\n", argv[1]);
        return 1;
    }
    si = av_find_best_stream(fmt, AVMEDIA_TYPE_VIDEO, -1, -1, &codec, 0);
    if (si < 0 || !(dec = avcodec_alloc_context3(codec)) ||
        avcodec_parameters_to_context(dec, fmt->streams[si]->codecpar) < 0 ||
        avcodec_open2(dec, codec, NULL) < 0) {
        fprintf(stderr, "video_probe: no decodable video stream in %s\n", argv[1]);
        return 1;
    }
    for (int flushing = 0;;) {
        if (!flushing) {
            rc = av_read_frame(fmt, pkt);
            if (rc < 0) {
                flushing = 1;
                avcodec_send_packet(dec, NULL);
            } else {
                if (pkt->stream_index == si)
                    avcodec_send_packet(dec, pkt);
                av_packet_unref(pkt);
            }
        }
        while ((rc = avcodec_receive_frame(dec, frame)) == 0) {
            if (frames++ == 0) {
                psnr = psnr_rgb(frame, png, w, h);
                psnr_luma = psnr_y(frame, png, w, h);
            }
            av_frame_unref(frame);
        }
        if (rc == AVERROR_EOF || (flushing && rc != 0 && rc != AVERROR(EAGAIN)))
            break;
    }
    printf("codec %s pix_fmt %s frames %d size %dx%d fps %d/%d psnr_y %.2f psnr_rgb %.2f\n",
           codec->name, av_get_pix_fmt_name(dec->pix_fmt), frames, dec->width, dec->height,
           fmt->streams[si]->avg_frame_rate.num, fmt->streams[si]->avg_frame_rate.den, psnr_luma,
           psnr);
    av_frame_free(&frame);
    av_packet_free(&pkt);
    avcodec_free_context(&dec);
    avformat_close_input(&fmt);
    free(png);
    return 0;
}
