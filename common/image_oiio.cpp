// Image file I/O through OpenImageIO: the only C++ in cube5. A thin shim, built as its own
// library (libc5image.so, loaded on the first image read or write: image_load.c), whose C API
// is image_oiio.h; no C++ exception ever crosses the extern "C" boundary.
//
// Writing: the format follows the extension, case-insensitive.
//   .png  8-bit RGB, no gamma. Each float v is clamped to [0,1] and quantised as
//         v8 = floor(v*255 + 0.5), evaluated in double precision from the float value
//         (round half up).
//   .exr  32-bit float RGB, values written exactly (zip compression, lossless).
// A NaN or an infinity anywhere is an error for both formats and nothing is written: the
// renderers keep every pixel finite (docs/scene-format.md, "Valid ranges"), so one that is
// not is a defect, never an image to hand on. The file is made in memory and written whole
// or not at all (atomic_file.h): a temporary beside PATH, every write, the sync and the close
// checked, then renamed over PATH.
//
// Reading: any format OpenImageIO knows; subimage 0, MIP level 0, the data window. One
// channel is replicated to RGB, two channels (grey + alpha) keep the grey, three or more
// keep the first three, as stored (alpha is not multiplied in). Values are converted to
// float by OpenImageIO (8-bit: v/255).

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

extern "C" {
#include "atomic_file.h"
#include "image_oiio.h"
}

namespace {

using OIIO::ImageInput;
using OIIO::ImageOutput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

const int kMaxSide = 16384;

// First line of an OpenImageIO error text, trailing white space removed.
std::string first_line(const std::string &s)
{
    std::string line = s.substr(0, s.find('\n'));
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t'))
        line.pop_back();
    if (line.empty())
        line = "unknown OpenImageIO error";
    return line;
}

unsigned char quantise8(float v)
{
    double d = v;
    if (!(d > 0.0))
        return 0; // also -0.0; NaN and infinities are refused before we get here
    if (d >= 1.0)
        return 255;
    return static_cast<unsigned char>(std::floor(d * 255.0 + 0.5));
}

// OpenImageIO's open errors do not always say why. Appends " (WHAT: reason)" to msg for
// the common causes, unless the reason is already in the message.
void add_reason(std::string &msg, const std::string &what, const std::string &reason)
{
    if (!reason.empty() && msg.find(reason) == std::string::npos)
        msg += " (" + what + ": " + reason + ")";
}

enum class Fmt { PNG, EXR };

// The parts of an output path and its format; refuses, naming `path`, what cannot be written
// whatever the pixels (c5_image_check_out).
struct OutPath {
    std::string dir, base, ext, lower;
    Fmt fmt;
};

int out_path(const char *path, OutPath &o, c5_err *err)
{
    if (c5_image_check_out(path, err) != 0) // image.c: the extension and the place
        return -1;
    const std::string p(path);
    const size_t slash = p.rfind('/');
    o.dir = slash == std::string::npos ? std::string() : p.substr(0, slash + 1);
    o.base = slash == std::string::npos ? p : p.substr(slash + 1);
    o.ext = o.base.substr(o.base.rfind('.'));
    o.lower = o.ext;
    for (char &c : o.lower)
        if (c >= 'A' && c <= 'Z')
            c = static_cast<char>(c - 'A' + 'a');
    o.fmt = o.lower == ".png" ? Fmt::PNG : Fmt::EXR;
    return 0;
}


int write_impl(const char *path, const c5_image *img, c5_err *err)
{
    OutPath op;
    if (out_path(path, op, err) != 0)
        return -1;
    if (!img || !img->rgb || img->w < 1 || img->w > kMaxSide || img->h < 1 || img->h > kMaxSide)
        return c5_fail(err, "%s: internal error: invalid image to write", path);
    const std::string &dir = op.dir, &base = op.base, &lower = op.lower;
    const Fmt fmt = op.fmt;

    const int w = img->w, h = img->h;
    const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h) * 3;
    for (size_t i = 0; i < n; i++)
        if (!std::isfinite(img->rgb[i])) {
            const size_t px = i / 3;
            return c5_fail(err, "%s: image has %s at pixel (%d,%d)", path,
                           std::isnan(img->rgb[i]) ? "NaN" : img->rgb[i] > 0 ? "+Inf" : "-Inf",
                           static_cast<int>(px % static_cast<size_t>(w)),
                           static_cast<int>(px / static_cast<size_t>(w)));
        }

    std::vector<unsigned char> bytes;
    if (fmt == Fmt::PNG) {
        bytes.resize(n);
        for (size_t i = 0; i < n; i++)
            bytes[i] = quantise8(img->rgb[i]);
    }

    // The file is made in memory (OpenImageIO's ioproxy), then written whole or not at all
    // (atomic_file.h): a writer that does not check its own writes cannot leave a truncated
    // file that looks written.
    std::vector<unsigned char> file;
    OIIO::Filesystem::IOVecOutput vec(file);
    OIIO::Filesystem::IOProxy *proxy = &vec;
    const std::string name = dir + base; // the writer's name for it in messages
    std::unique_ptr<ImageOutput> out = ImageOutput::create(name);
    if (!out)
        return c5_fail(err, "%s: cannot create %s writer: %s", path, lower.c_str() + 1,
                       first_line(OIIO::geterror()).c_str());
    if (!out->supports("ioproxy"))
        return c5_fail(err, "%s: the %s writer of this OpenImageIO cannot write to memory", path, lower.c_str() + 1);

    ImageSpec spec(w, h, 3, fmt == Fmt::PNG ? TypeDesc::UINT8 : TypeDesc::FLOAT);
    if (fmt == Fmt::EXR)
        spec.attribute("compression", "zip");
    /* An empty DateTime keeps OIIO from stamping the file (EXR capDate) with the time:
     * the same image must give the same file bytes on every run. */
    spec.attribute("DateTime", "");
    spec.attribute("oiio:ioproxy", TypeDesc::PTR, &proxy);

    if (!out->open(name, spec))
        return c5_fail(err, "%s: cannot write: %s", path, first_line(out->geterror()).c_str());
    const bool ok = fmt == Fmt::PNG ? out->write_image(TypeDesc::UINT8, bytes.data())
                                    : out->write_image(TypeDesc::FLOAT, img->rgb);
    if (!ok) {
        std::string e = first_line(out->geterror());
        out->close();
        return c5_fail(err, "%s: cannot write: %s", path, e.c_str());
    }
    if (!out->close())
        return c5_fail(err, "%s: cannot write: %s", path, first_line(out->geterror()).c_str());
    out.reset();
    return c5_afile_put(path, file.data(), file.size(), err);
}

int read_impl(const char *path, c5_image *img, c5_err *err)
{
    if (!path || !*path)
        return c5_fail(err, "image: no input path given");

    // Keep the stored colour values of files with alpha: without this hint OpenImageIO
    // premultiplies PNG colour by alpha while reading.
    ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    std::unique_ptr<ImageInput> in = ImageInput::open(path, &config);
    if (!in) {
        std::string e = first_line(OIIO::geterror());
        struct stat st;
        if (stat(path, &st) != 0)
            add_reason(e, "file", std::strerror(errno));
        return c5_fail(err, "%s: cannot read image: %s", path, e.c_str());
    }
    const ImageSpec &spec = in->spec();
    if (spec.deep)
        return c5_fail(err, "%s: deep images are not supported", path);
    if (spec.depth != 1)
        return c5_fail(err, "%s: 3-D images are not supported (depth %d)", path, spec.depth);
    if (spec.nchannels < 1)
        return c5_fail(err, "%s: image has no channels", path);

    c5_err aerr;
    if (c5_image_alloc(img, spec.width, spec.height, &aerr) != 0)
        return c5_fail(err, "%s: %s", path, aerr.msg);

    const int nread = spec.nchannels >= 3 ? 3 : 1;
    const OIIO::stride_t xs = static_cast<OIIO::stride_t>(3 * sizeof(float));
    const OIIO::stride_t ys = xs * spec.width;
    if (!in->read_image(in->current_subimage(), in->current_miplevel(), 0, nread,
                        TypeDesc::FLOAT, img->rgb, xs, ys)) {
        std::string e = first_line(in->geterror());
        c5_image_free(img);
        return c5_fail(err, "%s: cannot read image: %s", path, e.c_str());
    }
    in->close();
    if (nread == 1) {
        const size_t npx = static_cast<size_t>(img->w) * static_cast<size_t>(img->h);
        for (size_t i = 0; i < npx; i++)
            img->rgb[3 * i + 1] = img->rgb[3 * i + 2] = img->rgb[3 * i];
    }
    return 0;
}

} // namespace

extern "C" int c5_image_oiio_write(const char *path, const c5_image *img, c5_err *err)
{
    try {
        return write_impl(path, img, err);
    } catch (const std::exception &e) {
        return c5_fail(err, "%s: cannot write: %s", path ? path : "image", e.what());
    } catch (...) {
        return c5_fail(err, "%s: cannot write: unknown exception", path ? path : "image");
    }
}

// img is an output: it is overwritten (not freed first) and is left zeroed on failure.
extern "C" int c5_image_oiio_read(const char *path, c5_image *img, c5_err *err)
{
    if (!img)
        return c5_fail(err, "%s: internal error: no image to read into", path ? path : "image");
    img->w = img->h = 0;
    img->rgb = nullptr;
    try {
        return read_impl(path, img, err);
    } catch (const std::exception &e) {
        c5_image_free(img);
        return c5_fail(err, "%s: cannot read image: %s", path ? path : "image", e.what());
    } catch (...) {
        c5_image_free(img);
        return c5_fail(err, "%s: cannot read image: unknown exception", path ? path : "image");
    }
}
