// image/image_oiio.cpp -- the image codec through OpenImageIO: encode into memory, read, compare, text.  Built as
// the module libinstess_codec.so, which image/image_codec.c opens on the first call that needs it (the API is
// image/image.h's image_encode, image_read, ...; here they are codec_*).  The pixels and the writing of files are
// image/image.c and cli/run/output.c, in C, whose functions the loader hands over (codec_set_host).
//
// The library itself writes PNG and reads most PNGs (image/image_png.c, libpng) and compares (image/image_diff.c)
// without loading this module: OpenImageIO's libraries take ~0.4 s to load.  This module's PNG paths and
// codec_compare stay as they were: tests/test_image_codecs.c checks the library's against them, value for value.
//
// The only C++ file of the project.  Every entry point is extern "C", catches every exception and reports
// failures as -1 with a message in err that names the file and the reason.  Encoding goes into memory, not
// into the file, because OIIO 2.4's PNG writer ignores failed writes (a full disk would give a truncated
// file and success): cli/run/output.c writes the bytes with every write(2) checked.

#include "image_internal.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <strings.h>
#include <vector>

// The library's functions, handed over by the loader (codec_set_host) before any other entry point is called.
static const image_codec_host *g_host;
static const image_codec_host &H() { return *g_host; }


using namespace OIIO;

namespace {

const int kMaxDim = IS_IMAGE_MAX_DIM;  // largest width or height accepted
const char *const kFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

// printf into err (if given), always NUL-terminated.
void set_err(char *err, size_t errlen, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
void set_err(char *err, size_t errlen, const char *fmt, ...)
{
    if (!err || errlen == 0)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}

// True if w x h x channels is a size this module accepts.
bool size_ok(int w, int h, int channels)
{
    return w > 0 && h > 0 && w <= kMaxDim && h <= kMaxDim && channels > 0 && channels <= IS_IMAGE_MAX_CHANNELS;
}

// Check an image given to a writer; on failure a message naming `what`.
bool valid_image(const is_image *img, const char *what, char *err, size_t errlen)
{
    if (!img || !img->data || !size_ok(img->width, img->height, img->channels)) {
        set_err(err, errlen, "%s: invalid image (%dx%d, %d channels, data %s)", what, img ? img->width : 0,
                img ? img->height : 0, img ? img->channels : 0, img && img->data ? "set" : "NULL");
        return false;
    }
    return true;
}

// True for the colour channels that EXR stores as half.
bool is_rgba_name(const char *n)
{
    return !strcmp(n, "R") || !strcmp(n, "G") || !strcmp(n, "B") || !strcmp(n, "A");
}

// DateTime: OIIO stamps OpenEXR files with the current time unless DateTime is set, so two renders of the same
// scene would differ in those bytes.  It is set empty (no time stored), or to SOURCE_DATE_EPOCH (seconds since
// 1970, the reproducible-builds convention) when that is given.  PNG files carry no time.
void set_date_time(ImageSpec &spec)
{
    // Digits only (strtoll took " 1" and "+5"), 0..253402300799 (9999-12-31): the rule cli/run/output.c warns by.
    const char *e = getenv("SOURCE_DATE_EPOCH");
    size_t digits = e ? strspn(e, "0123456789") : 0;
    long long t = digits > 0 && digits <= 12 && !e[digits] ? strtoll(e, nullptr, 10) : -1;
    if (t < 0 || t > 253402300799LL) {
        spec.attribute("DateTime", "");
        return;
    }
    time_t tt = (time_t)t;
    struct tm tm;
    char buf[32];
    if (gmtime_r(&tt, &tm) && strftime(buf, sizeof buf, "%Y:%m:%d %H:%M:%S", &tm))
        spec.attribute("DateTime", buf);
}

// The spec of the file to write: names, per-channel formats, metadata; PNG keeps the first four channels.
ImageSpec make_spec(const is_image *img, is_image_format fmt, const is_image_meta *meta)
{
    int nch = fmt == IS_IMAGE_PNG ? std::min(img->channels, 4) : img->channels;
    ImageSpec spec(img->width, img->height, nch, fmt == IS_IMAGE_PNG ? TypeDesc::UINT8 : TypeDesc::HALF);
    spec.channelnames.clear();
    for (int c = 0; c < nch; c++) {
        spec.channelnames.emplace_back(img->channel_names[c]);
        if (fmt == IS_IMAGE_EXR)
            spec.channelformats.push_back(is_rgba_name(img->channel_names[c]) ? TypeDesc::HALF : TypeDesc::FLOAT);
    }
    spec.alpha_channel = -1;
    for (int c = 0; c < nch; c++)
        if (!strcmp(img->channel_names[c], "A"))
            spec.alpha_channel = c;
    int z = H().channel_index(img, "Z");
    spec.z_channel = z < nch ? z : -1;
    spec.attribute("oiio:UnassociatedAlpha", 1);  // store colour as given: no (un)premultiplication
    if (meta && meta->software)
        spec.attribute("Software", meta->software);
    if (meta && meta->description)
        spec.attribute("ImageDescription", meta->description);
    set_date_time(spec);
    return spec;
}

// PNG pixels: the first four channels clamped to [0, 1] and rounded to 8 bits (NaN becomes 0).
std::vector<unsigned char> quantize8(const is_image *img, int nch)
{
    std::vector<unsigned char> out((size_t)img->width * img->height * nch);
    size_t n = (size_t)img->width * img->height;
    for (size_t p = 0; p < n; p++)
        for (int c = 0; c < nch; c++) {
            float v = img->data[p * img->channels + c];
            v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;  // also maps NaN to 0
            out[p * nch + c] = (unsigned char)(v * 255.0f + 0.5f);
        }
    return out;
}

// Encode img as fmt into memory (bytes); false with a message naming label on failure.
bool encode(const is_image *img, is_image_format fmt, const char *label, const is_image_meta *meta,
            std::vector<unsigned char> &bytes, char *err, size_t errlen)
{
    const char *format_name = fmt == IS_IMAGE_PNG ? "png" : "openexr";
    auto out = ImageOutput::create(format_name);
    if (!out || !out->supports("ioproxy")) {
        set_err(err, errlen, "%s: no %s writer with memory output: %s", label, format_name,
                OIIO::geterror().c_str());
        return false;
    }
    Filesystem::IOVecOutput vec(bytes);
    ImageSpec spec = make_spec(img, fmt, meta);
    const char *name = fmt == IS_IMAGE_PNG ? "memory.png" : "memory.exr";
    if (!out->set_ioproxy(&vec) || !out->open(name, spec)) {
        set_err(err, errlen, "%s: cannot encode: %s", label, out->geterror().c_str());
        return false;
    }
    bool ok;
    if (fmt == IS_IMAGE_PNG) {
        std::vector<unsigned char> px = quantize8(img, spec.nchannels);
        ok = out->write_image(TypeDesc::UINT8, px.data());
    } else {
        ok = out->write_image(TypeDesc::FLOAT, img->data);
    }
    ok = out->close() && ok;
    if (!ok || bytes.empty())
        set_err(err, errlen, "%s: encoding failed: %s", label, out->geterror().c_str());
    return ok && !bytes.empty();
}

// Whether path, when its name ends in .exr (any case), starts with OpenEXR's magic number 76 2f 31 01; else false
// with "path: not an OpenEXR file" in err.  Files of other extensions pass.
bool exr_magic_ok(const char *path, char *err, size_t errlen)
{
    size_t n = strlen(path);
    if (n < 4 || strcasecmp(path + n - 4, ".exr") != 0) return true;
    unsigned char m[4] = {0, 0, 0, 0};
    FILE *f = fopen(path, "rb");
    size_t got = f ? fread(m, 1, 4, f) : 0;
    if (f) fclose(f);
    if (got == 4 && m[0] == 0x76 && m[1] == 0x2f && m[2] == 0x31 && m[3] == 0x01) return true;
    set_err(err, errlen, "%s: cannot read: not an OpenEXR file (no magic number 76 2f 31 01 at its start)", path);
    return false;
}

// The body of image_read (may throw; the caller catches).
int read_file(is_image *img, const char *path, char *err, size_t errlen)
{
    ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // return stored colour as is (no premultiplication)
    // ImageInput::open tries every other reader on a file the extension's reader refused, and some read it whole
    // (minutes for a large file of zeros named .exr): a file named .exr must start with OpenEXR's magic number
    // first.  (ImageInput::create without opening, which would avoid the fallback, leaves OpenImageIO's plugin
    // bookkeeping in a state that makes LeakSanitizer's thread scan crash at exit: the sanitizer stage saw it.)
    if (!exr_magic_ok(path, err, errlen)) return -1;
    auto in = ImageInput::open(path, &config);
    if (!in) {
        set_err(err, errlen, "%s: cannot read: %s", path, OIIO::geterror().c_str());
        return -1;
    }
    const ImageSpec spec = in->spec();   // the header: checked before any pixel is decoded
    if (!size_ok(spec.width, spec.height, spec.nchannels) || spec.depth > 1) {
        set_err(err, errlen, "%s: unsupported size %dx%dx%d with %d channels (at most %d channels, %d pixels wide)",
                path, spec.width, spec.height, spec.depth, spec.nchannels, IS_IMAGE_MAX_CHANNELS, kMaxDim);
        return -1;
    }
    unsigned long long values = (unsigned long long)spec.width * (unsigned long long)spec.height *
                                (unsigned long long)spec.nchannels;
    if (values > IS_IMAGE_MAX_VALUES) {
        set_err(err, errlen, "%s: the header declares %dx%d pixels with %d channels (%llu values), more than the limit "
                "of %llu (1 GiB of floats); nothing decoded", path, spec.width, spec.height, spec.nchannels, values,
                (unsigned long long)IS_IMAGE_MAX_VALUES);
        return -1;
    }
    if (spec.deep) {
        set_err(err, errlen, "%s: a deep image (several samples per pixel): instess reads flat images", path);
        return -1;
    }
    if (in->seek_subimage(1, 0)) {
        set_err(err, errlen, "%s: holds several parts or subimages: instess reads single-part images (compare the "
                "parts one by one, e.g. split with oiiotool)", path);
        return -1;
    }
    if (!in->seek_subimage(0, 0)) {
        set_err(err, errlen, "%s: cannot read: %s", path, in->geterror().c_str());
        return -1;
    }
    std::string names;
    for (int c = 0; c < spec.nchannels; c++) {
        std::string n(spec.channel_name(c));
        if (n.empty() || n.find(',') != std::string::npos)
            n = "channel" + std::to_string(c);  // unnamed or unrepresentable: name it by position
        names += (c ? "," : "") + n;
    }
    char why[512] = "";
    if (H().alloc(img, spec.width, spec.height, names.c_str(), why, sizeof why) != 0) {
        // image_alloc says which: channel names it cannot hold, or no memory for the pixels
        set_err(err, errlen, "%s: %s", path, why);
        return -1;
    }
    if (!in->read_image(0, 0, 0, spec.nchannels, TypeDesc::FLOAT, img->data)) {
        set_err(err, errlen, "%s: cannot read pixels: %s", path, in->geterror().c_str());
        H().free(img);
        return -1;
    }
    return 0;
}

// An ImageSpec describing img's float buffer.
ImageSpec float_spec(const is_image *img)
{
    ImageSpec spec(img->width, img->height, img->channels, TypeDesc::FLOAT);
    spec.channelnames.clear();
    for (int c = 0; c < img->channels; c++)
        spec.channelnames.emplace_back(img->channel_names[c]);
    spec.alpha_channel = -1;  // plain data: no algorithm may treat a channel as alpha
    return spec;
}

// The visual diff: dimmed luminance of a, plus |a - b| of the first three channels scaled so the largest
// difference is full brightness; pixels with a channel above fail_thresh are red, above warn yellow, from 35%
// to full brightness by their largest difference over the image's largest.
void fill_diff(const is_image *a, const is_image *b, float fail_thresh, float warn_thresh, float max_err,
               is_image *d)
{
    size_t n = (size_t)a->width * a->height;
    int ch = a->channels, nc = std::min(ch, 3);
    float scale = max_err > 0.0f ? 1.0f / max_err : 0.0f;
    for (size_t p = 0; p < n; p++) {
        const float *pa = a->data + p * ch, *pb = b->data + p * ch;
        float worst = 0.0f, lum = 0.0f, out[3];
        for (int c = 0; c < ch; c++)
            worst = std::max(worst, std::fabs(pa[c] - pb[c]));
        for (int c = 0; c < 3; c++) {
            lum += (c < nc ? pa[c] : pa[0]) / 3.0f;
            out[c] = std::fabs(pa[std::min(c, nc - 1)] - pb[std::min(c, nc - 1)]) * scale;
        }
        float *o = d->data + p * 4;
        for (int c = 0; c < 3; c++)
            o[c] = std::min(1.0f, 0.2f * std::min(std::max(lum, 0.0f), 1.0f) + out[c]);
        o[3] = 1.0f;
        float level = 0.35f + 0.65f * std::min(1.0f, worst * scale);  // amplified: the largest is full red
        if (worst > warn_thresh)
            o[0] = level, o[1] = level, o[2] = 0.0f;
        if (worst > fail_thresh)
            o[0] = level, o[1] = 0.0f, o[2] = 0.0f;
    }
}

// Write the visual diff of a and b to path.
int write_diff(const is_image *a, const is_image *b, float fail_thresh, float warn_thresh, float max_err,
               const char *path, char *err, size_t errlen)
{
    is_image d;
    if (H().alloc(&d, a->width, a->height, "R,G,B,A", err, errlen) != 0)
        return -1;
    fill_diff(a, b, fail_thresh, warn_thresh, max_err, &d);
    is_image_meta meta = {"instess " INSTESS_VERSION, "image_compare visual diff (red: fail, yellow: warn)"};
    int r = H().write(&d, path, &meta, err, errlen);
    H().free(&d);
    return r;
}

// The body of image_compare (may throw; the caller catches).
int compare_images(const is_image *a, const is_image *b, float fail_thresh, float warn_thresh, is_image_diff *res,
                   const char *diff_path, char *err, size_t errlen)
{
    if (!valid_image(a, "image_compare (first image)", err, errlen) ||
        !valid_image(b, "image_compare (second image)", err, errlen) || !res)
        return res ? -1 : (set_err(err, errlen, "image_compare: NULL result"), -1);
    if (a->width != b->width || a->height != b->height || a->channels != b->channels) {
        set_err(err, errlen, "image_compare: sizes differ (%dx%d with %d channels vs %dx%d with %d channels)",
                a->width, a->height, a->channels, b->width, b->height, b->channels);
        return -1;
    }
    ImageBuf A(float_spec(a), a->data), B(float_spec(b), b->data);
    ImageBufAlgo::CompareResults cr = ImageBufAlgo::compare(A, B, fail_thresh, warn_thresh);
    if (A.has_error() || B.has_error()) {
        set_err(err, errlen, "image_compare: %s%s", A.geterror().c_str(), B.geterror().c_str());
        return -1;
    }
    res->max_error = (float)cr.maxerror;
    res->mean_error = cr.meanerror;
    res->n_fail = (long)cr.nfail;
    res->n_warn = (long)cr.nwarn;
    res->n_pixels = (long)a->width * a->height;
    res->max_x = cr.maxx, res->max_y = cr.maxy, res->max_channel = cr.maxc;
    if (diff_path)
        return write_diff(a, b, fail_thresh, warn_thresh, res->max_error, diff_path, err, errlen);
    return 0;
}

// True if text is printable ASCII and newlines only.
bool ascii_text(const char *text)
{
    for (const unsigned char *p = (const unsigned char *)text; *p; p++)
        if ((*p < 0x20 && *p != '\n') || *p >= 0x7f)
            return false;
    return true;
}

// Pixel height of the font for size_px (OIIO takes whole pixels); 0 for a size outside 1..4096 (NaN too).
int font_px(float size_px)
{
    return size_px >= 0.5f && size_px < 4096.5f ? (int)std::lround(size_px) : 0;
}

// Whether the colour's four values are finite and in [0, 1] (a NaN would spread into every pixel drawn).
bool colour_ok(const float rgba[4])
{
    for (int k = 0; k < 4; k++)
        if (!(rgba[k] >= 0.0f && rgba[k] <= 1.0f))
            return false;
    return true;
}

// The body of image_draw_text: coverage of the text from render_text in a one-channel buffer over the
// text's box, then composited "over" the R, G, B (and A) channels only.
int draw_text(is_image *img, int x, int y, const char *text, float size_px, const float rgba[4], char *err,
              size_t errlen)
{
    int px = font_px(size_px);
    if (!valid_image(img, "image_draw_text", err, errlen))
        return -1;
    if (!text || !rgba || !(px >= 1 && px <= 4096) || !colour_ok(rgba)) {
        set_err(err, errlen, "image_draw_text: invalid argument (text %s, colour %s, size %g px; the colour's "
                "values 0..1, the size 1..4096)", text ? "set" : "NULL", rgba ? "set" : "NULL", (double)size_px);
        return -1;
    }
    int r = H().channel_index(img, "R"), g = H().channel_index(img, "G"), b = H().channel_index(img, "B");
    int a = H().channel_index(img, "A");
    if (r < 0 || g < 0 || b < 0) {
        set_err(err, errlen, "image_draw_text: the image has no R, G, B channels");
        return -1;
    }
    if (!ascii_text(text)) {
        set_err(err, errlen, "image_draw_text: \"%s\": only printable ASCII and '\\n' are supported "
                "(OpenImageIO 2.4's render_text draws other characters wrongly)", text);
        return -1;
    }
    if (!*text)
        return 0;
    ROI box = ImageBufAlgo::text_size(text, px, kFont);
    if (!box.defined()) {
        set_err(err, errlen, "image_draw_text: cannot use the font %s", kFont);
        return -1;
    }
    // The text's box in image coordinates, clipped to the image (in 64 bits: x and y may be any int); one
    // channel, one slice.
    const long long x0 = std::max((long long)box.xbegin + x, 0LL), x1 = std::min((long long)box.xend + x,
                                                                                   (long long)img->width);
    const long long y0 = std::max((long long)box.ybegin + y, 0LL), y1 = std::min((long long)box.yend + y,
                                                                                   (long long)img->height);
    if (x1 <= x0 || y1 <= y0)
        return 0;  // entirely outside the image
    box = ROI((int)x0, (int)x1, (int)y0, (int)y1, 0, 1, 0, 1);
    ImageBuf cov(ImageSpec(box, TypeDesc::FLOAT));
    ImageBufAlgo::zero(cov);
    const float one = 1.0f;
    if (!ImageBufAlgo::render_text(cov, x, y, text, px, kFont, cspan<float>(&one, 1))) {
        set_err(err, errlen, "image_draw_text: %s", cov.geterror().c_str());
        return -1;
    }
    for (int yy = box.ybegin; yy < box.yend; yy++)
        for (int xx = box.xbegin; xx < box.xend; xx++) {
            float k = std::min(std::max(cov.getchannel(xx, yy, 0, 0), 0.0f), 1.0f) * rgba[3];
            float *p = img->data + ((size_t)yy * img->width + xx) * img->channels;
            p[r] = rgba[0] * k + p[r] * (1.0f - k);
            p[g] = rgba[1] * k + p[g] * (1.0f - k);
            p[b] = rgba[2] * k + p[b] * (1.0f - k);
            if (a >= 0)
                p[a] = k + p[a] * (1.0f - k);
        }
    return 0;
}

}  // namespace

extern "C" {

// The interface version the loader checks before calling anything (CODEC_ABI in image/image_codec.c); its
// presence in the dynamic symbols marks the file as this module.
__attribute__((visibility("default"))) extern const int codec_abi;
const int codec_abi = 2;

void codec_set_host(const image_codec_host *host)
{
    g_host = host;
}

// Encode img as a PNG or EXR file in a malloc'd buffer.
int codec_encode(const is_image *img, is_image_format fmt, const is_image_meta *meta, const char *label,
                 unsigned char **bytes, size_t *len, char *err, size_t errlen)
{
    label = label ? label : "image";
    if (!bytes || !len || (fmt != IS_IMAGE_PNG && fmt != IS_IMAGE_EXR))
        return set_err(err, errlen, "%s: image_encode: bad arguments", label), -1;
    *bytes = nullptr, *len = 0;
    if (!valid_image(img, label, err, errlen))
        return -1;
    try {
        std::vector<unsigned char> v;
        if (!encode(img, fmt, label, meta, v, err, errlen))
            return -1;
        *bytes = (unsigned char *)malloc(v.size());
        if (!*bytes)
            return set_err(err, errlen, "%s: out of memory for %zu encoded bytes", label, v.size()), -1;
        memcpy(*bytes, v.data(), v.size());
        *len = v.size();
        return 0;
    } catch (const std::exception &e) {
        set_err(err, errlen, "%s: %s", label, e.what());
    } catch (...) {
        set_err(err, errlen, "%s: unknown error while encoding", label);
    }
    return -1;
}

// Read any image file into float channels.
int codec_read(is_image *img, const char *path, char *err, size_t errlen)
{
    if (!img || !path || !*path)
        return set_err(err, errlen, "image_read: %s", img ? "empty path" : "NULL image"), -1;
    memset(img, 0, sizeof *img);
    try {
        return read_file(img, path, err, errlen);
    } catch (const std::exception &e) {
        set_err(err, errlen, "%s: %s", path, e.what());
    } catch (...) {
        set_err(err, errlen, "%s: unknown error while reading", path);
    }
    H().free(img);
    return -1;
}

// Compare two images with ImageBufAlgo::compare and optionally write a visual diff.
int codec_compare(const is_image *a, const is_image *b, float fail_thresh, float warn_thresh, is_image_diff *res,
                  const char *diff_path, char *err, size_t errlen)
{
    try {
        return compare_images(a, b, fail_thresh, warn_thresh, res, diff_path, err, errlen);
    } catch (const std::exception &e) {
        set_err(err, errlen, "image_compare: %s", e.what());
    } catch (...) {
        set_err(err, errlen, "image_compare: unknown error");
    }
    return -1;
}

// Draw text with DejaVu Sans over the image's R, G, B, A; (x, y) is the left end of the baseline.
int codec_draw_text(is_image *img, int x, int y, const char *text, float size_px, const float rgba[4], char *err,
                    size_t errlen)
{
    try {
        return draw_text(img, x, y, text, size_px, rgba, err, errlen);
    } catch (const std::exception &e) {
        set_err(err, errlen, "image_draw_text: %s", e.what());
    } catch (...) {
        set_err(err, errlen, "image_draw_text: unknown error");
    }
    return -1;
}

// Size in pixels of the box image_draw_text would cover for text; 0 or -1.
int codec_text_size(const char *text, float size_px, int *w, int *h)
{
    try {
        int px = font_px(size_px);
        if (!text || !w || !h || !(px >= 1 && px <= 4096) || !ascii_text(text))
            return -1;
        *w = 0, *h = 0;
        if (!*text)
            return 0;
        ROI box = ImageBufAlgo::text_size(text, px, kFont);
        if (!box.defined())
            return -1;
        *w = box.width(), *h = box.height();
        return 0;
    } catch (...) {
        return -1;
    }
}

}  // extern "C"
