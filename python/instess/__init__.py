"""instess from Python: render a scene into a numpy array, compare images as the golden tests and
``instess compare`` do, read image files (an EXR's channels) -- through ctypes over libinstess.so, in this process.

    import instess
    img = instess.render("--mesh", "cube", "--patch", "smooth", "--size", "256x256")
    result = instess.compare(img, "golden.png", diff="diff.png")
    assert result, result          # passed; the repr says how many pixels differ and where

A process loads the library once, and with it everything a render and a comparison need: a test suite that
renders and compares two hundred scenes pays the start-up once (PNG is read and written through libpng; the
OpenImageIO codec, ~0.4 s to load, only for the first EXR).  Calls run one at a time (a lock), each in C.

Where the libraries are found, first found wins: $INSTESS_LIBDIR (a folder holding libinstess.so.0, with
libinstess_run.so beside it or in its instess/ folder); the folder ``make install`` wrote into _paths.py; the
repository's build/ folder when this package is the one in python/ of a built tree.  The codec module is looked
for beside libinstess_run.so (INSTESS_CODEC_DIR, unless set), and by the library in instess/ beside itself.
"""

import ctypes
import os
import threading

import numpy as np

__all__ = ["Image", "Comparison", "InstessError", "render", "read", "read_channels", "write", "compare"]


class InstessError(Exception):
    """A render, read, write or comparison that failed; the message is the library's (it names the file)."""


# ------------------------------------------------------------------------------------------------- the library

_MAX_CHANNELS = 32  # IS_IMAGE_MAX_CHANNELS (image/image.h)
_PNG, _EXR = 1, 2  # is_image_format


class _CImage(ctypes.Structure):
    """is_image (image/image.h)."""

    _fields_ = [("width", ctypes.c_int), ("height", ctypes.c_int), ("channels", ctypes.c_int),
                ("channel_names", (ctypes.c_char * 16) * _MAX_CHANNELS), ("data", ctypes.POINTER(ctypes.c_float))]


class _CDiff(ctypes.Structure):
    """is_image_diff (image/image.h)."""

    _fields_ = [("max_error", ctypes.c_float), ("mean_error", ctypes.c_double), ("n_fail", ctypes.c_long),
                ("n_warn", ctypes.c_long), ("n_pixels", ctypes.c_long), ("max_x", ctypes.c_int),
                ("max_y", ctypes.c_int), ("max_channel", ctypes.c_int), ("n_nonfinite", ctypes.c_long)]


class _CMeta(ctypes.Structure):
    """is_image_meta (image/image.h)."""

    _fields_ = [("software", ctypes.c_char_p), ("description", ctypes.c_char_p)]


def _folders():
    """(library folder, run module folders) pairs to try, in order."""
    env = os.environ.get("INSTESS_LIBDIR")
    if env:
        yield env, (env, os.path.join(env, "instess"))
    try:
        from . import _paths  # written by make install
        yield _paths.LIBDIR, (_paths.MODULEDIR,)
    except ImportError:
        pass
    build = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "build")
    yield build, (build,)


def _open():
    """libinstess.so and libinstess_run.so, opened from the first folder that has both."""
    tried = []
    for libdir, moddirs in _folders():
        libs = sorted(f for f in os.listdir(libdir) if f.startswith("libinstess.so.")) if os.path.isdir(libdir) else []
        mods = [os.path.join(d, "libinstess_run.so") for d in moddirs]
        mods = [m for m in mods if os.path.exists(m)]
        tried.append(libdir)
        if libs and mods:
            # the codec module: the library looks in instess/ beside itself (an install); a build tree keeps it
            # beside the library, which is said through INSTESS_CODEC_DIR (unless the caller set it)
            codec = os.path.dirname(os.path.abspath(mods[0]))  # absolute: a relative INSTESS_CODEC_DIR is refused
            if os.path.exists(os.path.join(codec, "libinstess_codec.so")):
                os.environ.setdefault("INSTESS_CODEC_DIR", codec)
            lib = ctypes.CDLL(os.path.join(libdir, libs[0]))  # the soname, libinstess.so.0, sorts first
            return lib, ctypes.CDLL(mods[0])
    raise InstessError("cannot find libinstess.so.0 with libinstess_run.so (looked in %s; set INSTESS_LIBDIR, or "
                       "build the repository: make, then make build/libinstess_run.so)" % ", ".join(tried))


_lib, _run = _open()
_lock = threading.Lock()
_ERRLEN = 4096

_lib.image_read.argtypes = [ctypes.POINTER(_CImage), ctypes.c_char_p, ctypes.c_char_p, ctypes.c_size_t]
_lib.image_write.argtypes = [ctypes.POINTER(_CImage), ctypes.c_char_p, ctypes.POINTER(_CMeta), ctypes.c_char_p,
                             ctypes.c_size_t]
_lib.image_free.argtypes = [ctypes.POINTER(_CImage)]
_lib.image_free.restype = None
_lib.image_check.argtypes = [ctypes.POINTER(_CImage), ctypes.POINTER(_CImage), ctypes.c_float, ctypes.c_float,
                             ctypes.c_char_p, ctypes.POINTER(_CDiff), ctypes.c_char_p, ctypes.c_size_t]
_lib.image_check.restype = ctypes.c_int
_run.scene_render_args.argtypes = [ctypes.c_int, ctypes.POINTER(ctypes.c_char_p), ctypes.c_int,
                                   ctypes.POINTER(_CImage), ctypes.c_char_p, ctypes.c_size_t, ctypes.c_char_p,
                                   ctypes.c_size_t]


def _text(buf):
    return buf.value.decode("utf-8", "replace")


def _bytes(path):
    return os.fsencode(path)


# ------------------------------------------------------------------------------------------------- images


class Image:
    """An image: ``pixels``, a float32 numpy array of height x width x channels (top row first, colour as display
    values in 0..1), and ``channels``, their names ("R", "G", "B", "A", "Z", "N.X", ...)."""

    def __init__(self, pixels, channels):
        pixels = np.asarray(pixels, dtype=np.float32)
        if pixels.ndim == 2:
            pixels = pixels[:, :, np.newaxis]
        if pixels.ndim != 3 or pixels.shape[2] != len(channels):
            raise ValueError("pixels must be height x width x %d (one plane per channel name)" % len(channels))
        self.pixels = pixels
        self.channels = tuple(channels)

    @property
    def width(self):
        return self.pixels.shape[1]

    @property
    def height(self):
        return self.pixels.shape[0]

    def channel(self, name):
        """The plane of channel ``name`` (height x width); KeyError when there is none."""
        if name not in self.channels:
            raise KeyError("no channel %r (the image has %s)" % (name, ",".join(self.channels)))
        return self.pixels[:, :, self.channels.index(name)]

    def select(self, *names):
        """A new image of the channels named, in that order: ``img.select("R", "G", "B", "A")``."""
        return Image(np.stack([self.channel(n) for n in names], axis=2), names)

    def __repr__(self):
        return "instess.Image(%dx%d, channels %s)" % (self.width, self.height, ",".join(self.channels))


def _from_c(c):
    """An Image copied out of an is_image (which the caller frees)."""
    n = c.width * c.height * c.channels
    data = np.ctypeslib.as_array(c.data, shape=(n,)).copy() if n else np.zeros(0, np.float32)
    names = [c.channel_names[k].value.decode() for k in range(c.channels)]
    return Image(data.reshape(c.height, c.width, c.channels), names)


def _to_c(img):
    """An is_image over img's pixels (no copy; keep img alive while it is used) and the array it points into."""
    if not isinstance(img, Image):
        raise TypeError("an instess.Image or a file name is needed, not %r" % type(img).__name__)
    if len(img.channels) > _MAX_CHANNELS or any(len(n.encode()) > 15 or "," in n or not n for n in img.channels):
        raise ValueError("channel names: 1 to %d names of 1 to 15 characters without commas" % _MAX_CHANNELS)
    pixels = np.ascontiguousarray(img.pixels, dtype=np.float32)
    c = _CImage(img.width, img.height, len(img.channels))
    for k, name in enumerate(img.channels):
        c.channel_names[k].value = name.encode()
    c.data = pixels.ctypes.data_as(ctypes.POINTER(ctypes.c_float))
    return c, pixels


def render(*args, format="png"):
    """What ``instess ARGS -o FILE.png`` (format="png") or ``FILE.exr`` (format="exr") would write, as an Image,
    rendered in this process and not written: the same options (``instess --help``), the same pixels.

    A PNG holds the image's first four channels, R, G, B and A, as 8-bit values: that is what is returned, the
    values k / 255 that reading the file gives.  An EXR holds R, G, B, A as half floats, then Z and the AOVs of
    --aov as floats, in the order reading it gives (OpenEXR sorts channels by name): the image is encoded and
    read back through a temporary file, as a golden EXR is read.  Arguments may be one list or several strings.  The
    loader's warnings and changes made to what was asked come as Python warnings (UserWarning); a usage or input
    error raises InstessError with the program's message."""
    if len(args) == 1 and isinstance(args[0], (list, tuple)):
        args = tuple(args[0])
    if format not in ("png", "exr"):
        raise ValueError("format must be 'png' or 'exr'")
    argv = (ctypes.c_char_p * (len(args) + 1))(*[os.fsencode(str(a)) for a in args], None)
    c, notes, err = _CImage(), ctypes.create_string_buffer(_ERRLEN), ctypes.create_string_buffer(_ERRLEN)
    with _lock:
        rc = _run.scene_render_args(len(args), argv, _EXR if format == "exr" else _PNG, ctypes.byref(c), notes,
                                    _ERRLEN, err, _ERRLEN)
    if _text(notes):
        import warnings
        for line in _text(notes).splitlines():
            warnings.warn("instess: " + line, stacklevel=2)
    if rc != 0:
        raise InstessError(_text(err))
    try:
        if format == "exr":
            import tempfile
            with tempfile.TemporaryDirectory(prefix="instess-") as tmp:
                path = os.path.join(tmp, "render.exr")
                with _lock:
                    rc = _lib.image_write(ctypes.byref(c), _bytes(path), None, err, _ERRLEN)
                if rc != 0:
                    raise InstessError(_text(err))
                return read(path)
        img = _from_c(c)
    finally:
        _lib.image_free(ctypes.byref(c))
    return img.select(*img.channels[:4])


def read(path):
    """The image file at path (PNG, EXR or anything OpenImageIO reads) as an Image: its channels as the file
    names them (Y for a grey PNG), values as stored (8-bit k / 255)."""
    c, err = _CImage(), ctypes.create_string_buffer(_ERRLEN)
    with _lock:
        rc = _lib.image_read(ctypes.byref(c), _bytes(path), err, _ERRLEN)
    if rc != 0:
        raise InstessError(_text(err))
    try:
        return _from_c(c)
    finally:
        _lib.image_free(ctypes.byref(c))


def read_channels(path):
    """The channels of the image file at path (an EXR's R, G, B, A, Z and AOVs such as N.X or depth) as a dict of
    name -> height x width float32 array, in the file's order."""
    img = read(path)
    return {name: img.pixels[:, :, k].copy() for k, name in enumerate(img.channels)}


def write(img, path, description=None):
    """Write img to path (.png: its first four channels, 8 bits; .exr: RGBA half, the rest float) atomically
    (through a temporary beside it, renamed: nothing is left on failure)."""
    c, keep = _to_c(img)
    meta = _CMeta(b"instess (python)", description.encode() if description is not None else None)
    err = ctypes.create_string_buffer(_ERRLEN)
    with _lock:
        rc = _lib.image_write(ctypes.byref(c), _bytes(path), ctypes.byref(meta), err, _ERRLEN)
    del keep
    if rc != 0:
        raise InstessError(_text(err))


# ------------------------------------------------------------------------------------------------- comparison

# image_check's verdicts (is_image_verdict) -> (name, exit code of `instess compare`)
_VERDICTS = {0: ("pass", 0), 1: ("different", 1), 2: ("shape", 3), 3: ("unreadable", 4)}


class Comparison:
    """The result of compare(): ``verdict`` ("pass", "different", "shape" or "unreadable"), ``exit_code`` (what
    ``instess compare`` exits with: 0, 1, 3, 4), ``passed``, and the numbers it prints: ``n_pixels``,
    ``n_fail`` (pixels with a channel more than ``fail`` apart, or a non-finite mismatch), ``n_nonfinite``,
    ``max_error`` at (``max_x``, ``max_y``) in channel ``max_channel``, ``mean_error``; ``message`` for "shape"
    and "unreadable".  True when it passed, so ``assert instess.compare(a, b), ...`` reads as a test."""

    def __init__(self, verdict, diff, message, diff_path):
        self.verdict, self.exit_code = _VERDICTS[verdict]
        self.passed = self.verdict == "pass"
        self.message = message
        self.diff = os.fspath(diff_path) if diff_path is not None and self.verdict == "different" else None
        for name, _ in _CDiff._fields_:
            setattr(self, name, getattr(diff, name))

    def __bool__(self):
        return self.passed

    def __repr__(self):
        if self.verdict in ("shape", "unreadable"):
            return "instess.Comparison(%s: %s)" % (self.verdict, self.message)
        return ("instess.Comparison(%s: %d of %d pixels fail, largest difference %g at pixel %d,%d channel %d, "
                "mean %g%s)" % (self.verdict, self.n_fail, self.n_pixels, self.max_error, self.max_x, self.max_y,
                                self.max_channel, self.mean_error, "; diff image " + self.diff if self.diff else ""))


def compare(actual, reference, fail=0.0, failpercent=0.0, diff=None):
    """The golden tests' pixel-diff test (image_check), with the verdicts and numbers of
    ``instess compare ACTUAL REFERENCE --fail T --failpercent P --diff FILE``: a pixel fails when one of its
    channels differs by more than ``fail`` (or is NaN or infinite in one image and not the same in the other);
    the test passes when at most ``failpercent`` percent of the pixels fail (0 and 0: any difference fails).
    actual and reference are Images or image file names.  When they differ and ``diff`` names a .png or .exr
    file, the amplified diff image is written there.  Returns a Comparison (true when it passed)."""
    err = ctypes.create_string_buffer(_ERRLEN)
    images, keep = [], []
    for x in (actual, reference):
        if isinstance(x, Image):
            images.append(x)
            continue
        try:
            images.append(read(x))
        except InstessError as e:
            return Comparison(3, _CDiff(), str(e), None)
    (ca, ka), (cb, kb) = _to_c(images[0]), _to_c(images[1])
    d = _CDiff()
    with _lock:
        v = _lib.image_check(ctypes.byref(ca), ctypes.byref(cb), float(fail), float(failpercent),
                             _bytes(diff) if diff is not None else None, ctypes.byref(d), err, _ERRLEN)
    del ka, kb
    return Comparison(v, d, _text(err) if v >= 2 else "", diff)
