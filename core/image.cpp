// core/image.cpp -- image files, comparison and text through OpenImageIO (the API is in core/core.h).
//
// The only C++ file of the project.  Every entry point is extern "C", catches every exception and reports
// failures as -1 with a message in err that names the path and the reason.  Files are written atomically:
// a temporary ".<stem>.tmp-<pid>-XXXXXX<ext>" beside the target (the real extension stays last because OIIO
// picks the format from it), fsync, rename(2) over the target, fsync of the directory.  OIIO encodes into
// memory and this file writes the bytes, checking every write (OIIO 2.4's PNG writer ignores write errors).
// The temporary file's name sits in a static slot while it exists, for image_remove_temp_files (a signal
// handler's clean-up; see core.h).

#include "core.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

using namespace OIIO;

namespace {

const int kMaxDim = 1 << 16;  // largest width or height accepted (PNG and EXR handle more; we do not need it)
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

// The file formats image_write produces.
enum class Fmt { None, Png, Exr };

// Lower-case extension of path (with the dot), or "" when there is none after the last '/'.
std::string extension_of(const std::string &path)
{
    size_t slash = path.rfind('/');
    size_t dot = path.rfind('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash))
        return "";
    std::string ext = path.substr(dot);
    for (char &c : ext)
        c = (char)tolower((unsigned char)c);
    return ext;
}

// The output format chosen by a path's extension.
Fmt format_of(const std::string &path)
{
    std::string ext = extension_of(path);
    return ext == ".png" ? Fmt::Png : ext == ".exr" ? Fmt::Exr : Fmt::None;
}

// Directory part of path ("." when none).
std::string dir_of(const std::string &path)
{
    size_t slash = path.rfind('/');
    if (slash == std::string::npos)
        return ".";
    return slash == 0 ? "/" : path.substr(0, slash);
}

// File name part of path.
std::string base_of(const std::string &path)
{
    size_t slash = path.rfind('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
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

// Index of the channel called name, or -1.
int channel_index(const is_image *img, const char *name)
{
    for (int c = 0; c < img->channels; c++)
        if (!strcmp(img->channel_names[c], name))
            return c;
    return -1;
}

// DateTime: OIIO stamps OpenEXR files with the current time, so two renders of the same scene differ in those
// bytes.  SOURCE_DATE_EPOCH (seconds since 1970, the reproducible-builds convention) fixes it: then the same
// render gives the same file.  PNG files carry no time.
void set_date_time(ImageSpec &spec)
{
    const char *e = getenv("SOURCE_DATE_EPOCH");
    char *end = nullptr;
    long long t = e ? strtoll(e, &end, 10) : -1;
    if (!e || end == e || *end || t < 0 || t > 253402300799LL)  // up to 9999-12-31
        return;
    time_t tt = (time_t)t;
    struct tm tm;
    char buf[32];
    if (gmtime_r(&tt, &tm) && strftime(buf, sizeof buf, "%Y:%m:%d %H:%M:%S", &tm))
        spec.attribute("DateTime", buf);
}

// The spec of the file to write: names, per-channel formats, metadata; PNG keeps the first four channels.
ImageSpec make_spec(const is_image *img, Fmt fmt, const is_image_meta *meta)
{
    int nch = fmt == Fmt::Png ? std::min(img->channels, 4) : img->channels;
    ImageSpec spec(img->width, img->height, nch, fmt == Fmt::Png ? TypeDesc::UINT8 : TypeDesc::HALF);
    spec.channelnames.clear();
    for (int c = 0; c < nch; c++) {
        spec.channelnames.emplace_back(img->channel_names[c]);
        if (fmt == Fmt::Exr)
            spec.channelformats.push_back(is_rgba_name(img->channel_names[c]) ? TypeDesc::HALF : TypeDesc::FLOAT);
    }
    spec.alpha_channel = -1;
    for (int c = 0; c < nch; c++)
        if (!strcmp(img->channel_names[c], "A"))
            spec.alpha_channel = c;
    int z = channel_index(img, "Z");
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

// Encode img as the file format `fmt` into memory (bytes); false with a message on failure.  Encoding into
// memory, not into the file, because OIIO 2.4's PNG writer ignores failed writes (a full disk would give a
// truncated file and success): the bytes are written below with every write(2) checked.
bool encode(const is_image *img, Fmt fmt, const std::string &path, const is_image_meta *meta,
            std::vector<unsigned char> &bytes, char *err, size_t errlen)
{
    auto out = ImageOutput::create(path);
    if (!out || !out->supports("ioproxy")) {
        set_err(err, errlen, "%s: no image writer with memory output: %s", path.c_str(), OIIO::geterror().c_str());
        return false;
    }
    Filesystem::IOVecOutput vec(bytes);
    ImageSpec spec = make_spec(img, fmt, meta);
    if (!out->set_ioproxy(&vec) || !out->open(path, spec)) {
        set_err(err, errlen, "%s: cannot encode: %s", path.c_str(), out->geterror().c_str());
        return false;
    }
    bool ok;
    if (fmt == Fmt::Png) {
        std::vector<unsigned char> px = quantize8(img, spec.nchannels);
        ok = out->write_image(TypeDesc::UINT8, px.data());
    } else {
        ok = out->write_image(TypeDesc::FLOAT, img->data);
    }
    ok = out->close() && ok;
    if (!ok || bytes.empty())
        set_err(err, errlen, "%s: encoding failed: %s", path.c_str(), out->geterror().c_str());
    return ok && !bytes.empty();
}

// Write all bytes to fd, fsync and close it; false with a message naming path on any failure.
bool write_fd(int fd, const std::vector<unsigned char> &bytes, const std::string &path, char *err, size_t errlen)
{
    size_t done = 0;
    while (done < bytes.size()) {
        ssize_t n = write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            set_err(err, errlen, "%s: write failed after %zu of %zu bytes: %s", path.c_str(), done, bytes.size(),
                    n < 0 ? strerror(errno) : "no progress");
            close(fd);
            return false;
        }
        done += (size_t)n;
    }
    if (fsync(fd) != 0 || close(fd) != 0) {
        set_err(err, errlen, "%s: fsync / close failed: %s", path.c_str(), strerror(errno));
        return false;
    }
    return true;
}

// fsync the directory (makes the rename durable; some filesystems cannot, which is harmless here).
void fsync_dir(const std::string &dir)
{
    int fd = open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        (void)fsync(fd);
        close(fd);
    }
}

// ---- temporary files that a signal handler may remove (image_remove_temp_files, core.h) ----
// The one accepted exception to "no globals except const tables": a signal handler reaches nothing but
// statics.  A slot's state: 0 free, 1 claimed, 2 path valid (the file may exist; the handler unlinks it).
const int kTempSlots = 8;
const size_t kTempPathMax = 4096;
struct TempSlot {
    std::atomic<int> state;
    char path[kTempPathMax];
};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler needs lock-free atomics");
TempSlot g_temp_slots[kTempSlots];  // zero-initialised: all free

// Claim a slot holding path (state 2); its index, or -1 when all are busy or the path is too long.
int temp_claim(const char *path)
{
    size_t n = strlen(path);
    if (n >= kTempPathMax)
        return -1;
    for (int s = 0; s < kTempSlots; s++) {
        int expected = 0;
        if (g_temp_slots[s].state.compare_exchange_strong(expected, 1)) {
            memcpy(g_temp_slots[s].path, path, n + 1);
            g_temp_slots[s].state.store(2);
            return s;
        }
    }
    return -1;
}

// Free slot s (after the rename or the unlink of its file); -1 is ignored.
void temp_release(int s)
{
    if (s >= 0 && s < kTempSlots)
        g_temp_slots[s].state.store(0);
}

// INSTESS_TEST_WRITE_DELAY_MS=N: sleep N ms with the temporary file complete and not yet renamed (tests
// signal the program in that window).
void test_write_delay()
{
    const char *d = getenv("INSTESS_TEST_WRITE_DELAY_MS");
    long ms = d ? strtol(d, nullptr, 10) : 0;
    if (ms <= 0 || ms > 60000)
        return;
    struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR) {
    }
}

// Create the temporary file ".<stem>.tmp-<pid>-XXXXXX<ext>" beside path; its fd, or -1.  The name goes to tmp
// and into a temp slot (*slot, -1 if none was free) from before the file exists, so that a signal arriving
// at any later moment can remove it; mkstemps fills the X's in the slot itself.
int make_temp(const std::string &path, std::string &tmp, int *slot, char *err, size_t errlen)
{
    std::string ext = path.substr(path.rfind('.'));
    std::string base = base_of(path);
    std::string stem = base.substr(0, base.size() - ext.size());
    std::string tmpl = dir_of(path) + "/." + stem + ".tmp-" + std::to_string((long)getpid()) + "-XXXXXX" + ext;
    std::vector<char> buf(tmpl.begin(), tmpl.end());
    buf.push_back('\0');
    tmp.reserve(buf.size());  // no allocation (and no exception) once the file exists
    *slot = temp_claim(buf.data());
    char *name = *slot >= 0 ? g_temp_slots[*slot].path : buf.data();
    int fd = mkstemps(name, (int)ext.size());
    if (fd < 0) {
        set_err(err, errlen, "%s: cannot create a temporary file in %s: %s", path.c_str(), dir_of(path).c_str(),
                strerror(errno));
        temp_release(*slot);
        *slot = -1;
        return -1;
    }
    tmp.assign(name);
    (void)fchmod(fd, 0644);  // mkstemps makes 0600; images are for everyone to read
    return fd;
}

// Check the target path before writing: non-empty, known extension, not a directory.
bool check_target(const char *path, Fmt *fmt, char *err, size_t errlen)
{
    if (!path || !*path) {
        set_err(err, errlen, "image_write: empty output path");
        return false;
    }
    *fmt = format_of(path);
    if (*fmt == Fmt::None) {
        set_err(err, errlen, "%s: unknown image extension \"%s\" (use .png or .exr)", path,
                extension_of(path).c_str());
        return false;
    }
    struct stat st;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        set_err(err, errlen, "%s: is a directory", path);
        return false;
    }
    if (base_of(path).size() == extension_of(path).size()) {
        set_err(err, errlen, "%s: the file name has no stem before its extension", path);
        return false;
    }
    return true;
}

// The body of image_write (may throw; the caller catches): encode, temporary, write + fsync, rename.
int write_atomic(const is_image *img, const char *path_c, const is_image_meta *meta, char *err, size_t errlen)
{
    Fmt fmt;
    if (!check_target(path_c, &fmt, err, errlen) || !valid_image(img, path_c, err, errlen))
        return -1;
    std::string path(path_c), tmp;
    std::vector<unsigned char> bytes;
    if (!encode(img, fmt, path, meta, bytes, err, errlen))
        return -1;
    int slot = -1;
    int fd = make_temp(path, tmp, &slot, err, errlen);
    if (fd < 0)
        return -1;
    bool ok = write_fd(fd, bytes, path, err, errlen);
    if (ok)
        test_write_delay();
    if (ok && rename(tmp.c_str(), path.c_str()) != 0) {
        set_err(err, errlen, "%s: cannot rename the temporary file into place: %s", path.c_str(), strerror(errno));
        ok = false;
    }
    if (!ok)
        unlink(tmp.c_str());
    temp_release(slot);
    if (!ok)
        return -1;
    fsync_dir(dir_of(path));
    return 0;
}

// The body of image_read (may throw; the caller catches).
int read_file(is_image *img, const char *path, char *err, size_t errlen)
{
    ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // return stored colour as is (no premultiplication)
    auto in = ImageInput::open(path, &config);
    if (!in) {
        set_err(err, errlen, "%s: cannot read: %s", path, OIIO::geterror().c_str());
        return -1;
    }
    const ImageSpec &spec = in->spec();
    if (!size_ok(spec.width, spec.height, spec.nchannels) || spec.depth > 1) {
        set_err(err, errlen, "%s: unsupported size %dx%dx%d with %d channels (at most %d channels, %d pixels wide)",
                path, spec.width, spec.height, spec.depth, spec.nchannels, IS_IMAGE_MAX_CHANNELS, kMaxDim);
        return -1;
    }
    std::string names;
    for (int c = 0; c < spec.nchannels; c++) {
        std::string n(spec.channel_name(c));
        if (n.empty() || n.find(',') != std::string::npos)
            n = "channel" + std::to_string(c);  // unnamed or unrepresentable: name it by position
        names += (c ? "," : "") + n;
    }
    if (image_alloc(img, spec.width, spec.height, names.c_str(), err, errlen) != 0) {
        set_err(err, errlen, "%s: unsupported channel names \"%s\" (at most 15 characters each)", path,
                names.c_str());
        return -1;
    }
    if (!in->read_image(0, 0, 0, spec.nchannels, TypeDesc::FLOAT, img->data)) {
        set_err(err, errlen, "%s: cannot read pixels: %s", path, in->geterror().c_str());
        image_free(img);
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
// difference is full brightness; pixels with a channel above fail_thresh are pure red, above warn yellow.
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
        if (worst > warn_thresh)
            o[0] = 1.0f, o[1] = 1.0f, o[2] = 0.0f;
        if (worst > fail_thresh)
            o[0] = 1.0f, o[1] = 0.0f, o[2] = 0.0f;
    }
}

// Write the visual diff of a and b to path.
int write_diff(const is_image *a, const is_image *b, float fail_thresh, float warn_thresh, float max_err,
               const char *path, char *err, size_t errlen)
{
    is_image d;
    if (image_alloc(&d, a->width, a->height, "R,G,B,A", err, errlen) != 0)
        return -1;
    fill_diff(a, b, fail_thresh, warn_thresh, max_err, &d);
    is_image_meta meta = {"instess " INSTESS_VERSION, "image_compare visual diff (red: fail, yellow: warn)"};
    int r = image_write(&d, path, &meta, err, errlen);
    image_free(&d);
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

// Pixel height of the font for size_px (OIIO takes whole pixels).
int font_px(float size_px)
{
    return (int)std::lround(size_px);
}

// The body of image_draw_text: coverage of the text from render_text in a one-channel buffer over the
// text's box, then composited "over" the R, G, B (and A) channels only.
int draw_text(is_image *img, int x, int y, const char *text, float size_px, const float rgba[4], char *err,
              size_t errlen)
{
    int px = font_px(size_px);
    if (!valid_image(img, "image_draw_text", err, errlen))
        return -1;
    if (!text || !rgba || !(px >= 1 && px <= 4096)) {
        set_err(err, errlen, "image_draw_text: invalid argument (text %s, colour %s, size %g px)",
                text ? "set" : "NULL", rgba ? "set" : "NULL", (double)size_px);
        return -1;
    }
    int r = channel_index(img, "R"), g = channel_index(img, "G"), b = channel_index(img, "B");
    int a = channel_index(img, "A");
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
    // The text's box in image coordinates, clipped to the image; one channel, one slice.
    box = ROI(std::max(box.xbegin + x, 0), std::min(box.xend + x, img->width), std::max(box.ybegin + y, 0),
              std::min(box.yend + y, img->height), 0, 1, 0, 1);
    if (box.width() <= 0 || box.height() <= 0)
        return 0;  // entirely outside the image
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

// Split "R,G,B" into names; false if a name is empty or too long, or there are too many.
bool parse_names(const char *list, std::vector<std::string> &names)
{
    std::string s(list);
    size_t start = 0;
    for (;;) {
        size_t comma = s.find(',', start);
        std::string n = s.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (n.empty() || n.size() >= sizeof(((is_image *)nullptr)->channel_names[0]))
            return false;
        names.push_back(n);
        if (comma == std::string::npos)
            return names.size() <= IS_IMAGE_MAX_CHANNELS;
        start = comma + 1;
    }
}

}  // namespace

extern "C" {

// Allocate a zeroed image with the given comma-separated channel names.
int image_alloc(is_image *img, int width, int height, const char *channel_names, char *err, size_t errlen)
{
    if (!img)
        return set_err(err, errlen, "image_alloc: NULL image"), -1;
    memset(img, 0, sizeof *img);
    try {
        std::vector<std::string> names;
        if (!channel_names || !parse_names(channel_names, names)) {
            set_err(err, errlen, "image_alloc: bad channel names \"%s\" (1 to %d names of 1 to 15 characters)",
                    channel_names ? channel_names : "(null)", IS_IMAGE_MAX_CHANNELS);
            return -1;
        }
        if (!size_ok(width, height, (int)names.size())) {
            set_err(err, errlen, "image_alloc: bad size %dx%d (1 to %d pixels each way)", width, height, kMaxDim);
            return -1;
        }
        img->data = (float *)calloc((size_t)width * height * names.size(), sizeof(float));
        if (!img->data) {
            set_err(err, errlen, "image_alloc: out of memory for %dx%d x %zu channels", width, height, names.size());
            return -1;
        }
        img->width = width, img->height = height, img->channels = (int)names.size();
        for (size_t c = 0; c < names.size(); c++)
            snprintf(img->channel_names[c], sizeof img->channel_names[c], "%s", names[c].c_str());
        return 0;
    } catch (const std::exception &e) {
        set_err(err, errlen, "image_alloc: %s", e.what());
        return -1;
    }
}

// Free the pixels and zero the struct (safe on a zeroed or already freed image).
void image_free(is_image *img)
{
    if (!img)
        return;
    free(img->data);
    memset(img, 0, sizeof *img);
}

// Fill the channels named R, G, B, A from packed R | G<<8 | B<<16 | A<<24 pixels (k / 255, as PNG reads back).
void image_from_rgba8(is_image *img, const uint32_t *rgba)
{
    if (!img || !img->data || !rgba)
        return;
    int idx[4] = {channel_index(img, "R"), channel_index(img, "G"), channel_index(img, "B"), channel_index(img, "A")};
    size_t n = (size_t)img->width * img->height;
    for (size_t p = 0; p < n; p++)
        for (int k = 0; k < 4; k++)
            if (idx[k] >= 0)
                img->data[p * img->channels + idx[k]] = (float)((rgba[p] >> (8 * k)) & 0xffu) * (1.0f / 255.0f);
}

// Write img atomically to a .png or .exr path.
// Unlink every temporary file being written: async-signal-safe (lock-free atomic loads and unlink(2) only).
void image_remove_temp_files(void)
{
    for (int s = 0; s < kTempSlots; s++)
        if (g_temp_slots[s].state.load() == 2)
            unlink(g_temp_slots[s].path);
}

int image_temp_track(const char *path)
{
    return path ? temp_claim(path) : -1;
}

void image_temp_untrack(int slot)
{
    temp_release(slot);
}

int image_write(const is_image *img, const char *path, const is_image_meta *meta, char *err, size_t errlen)
{
    try {
        return write_atomic(img, path, meta, err, errlen);
    } catch (const std::exception &e) {
        set_err(err, errlen, "%s: %s", path ? path : "(null)", e.what());
    } catch (...) {
        set_err(err, errlen, "%s: unknown error while writing", path ? path : "(null)");
    }
    return -1;
}

// Read any image file into float channels.
int image_read(is_image *img, const char *path, char *err, size_t errlen)
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
    image_free(img);
    return -1;
}

// Compare two images with ImageBufAlgo::compare and optionally write a visual diff.
int image_compare(const is_image *a, const is_image *b, float fail_thresh, float warn_thresh, is_image_diff *res,
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
int image_draw_text(is_image *img, int x, int y, const char *text, float size_px, const float rgba[4], char *err,
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
int image_text_size(const char *text, float size_px, int *w, int *h)
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
