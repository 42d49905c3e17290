"""python/tests/test_instess.py -- the Python package (python/instess) as a pixel-diff test suite uses it.

The first test is the example: a golden test of a few scenes, the way a project's own pytest suite would write
one (render in this process, compare with the reference, the amplified diff image written on a difference).  The
others check that the package says what the program says: a render is the file ``instess ARGS -o`` writes, value
for value (PNG and EXR); compare()'s verdicts and counts are ``instess compare``'s; an EXR's channels read back;
errors and warnings come through.  Run by ``make python-check`` (a stage of ``make test``)::

    PYTHONPATH=python INSTESS_LIBDIR=build python3 -m pytest -v python/tests
"""

import os
import re
import subprocess

import numpy as np
import pytest

import instess

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BIN = os.environ.get("INSTESS_BIN", os.path.join(ROOT, "build", "instess"))


def program(*args, cwd=None):
    """Run the instess program: (exit code, stdout)."""
    p = subprocess.run([BIN, *map(str, args)], cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    return p.returncode, p.stdout


# --------------------------------------------------------------------------------------------- the example

SCENES = {
    "cube-smooth": ["--mesh", "cube", "--patch", "smooth"],
    "octahedron-npatch": ["--mesh", "octahedron", "--patch", "npatch", "--level", "4"],
    "sphere-phong-wire": ["--mesh", "sphere", "--patch", "phong", "--fill", "solid+wire"],
}


@pytest.mark.parametrize("name", sorted(SCENES))
def test_golden_example(name, tmp_path):
    """A golden test: render, compare with the reference; a difference fails with the numbers and a diff image.
    (Here the reference is made by the program first; a project keeps its references in its repository.)"""
    golden = tmp_path / (name + ".png")
    assert program(*SCENES[name], "--size", "128x96", "-q", "-o", golden)[0] == 0
    actual = instess.render(*SCENES[name], "--size", "128x96")
    result = instess.compare(actual, golden, diff=tmp_path / (name + ".diff.png"))
    assert result, result
    assert not (tmp_path / (name + ".diff.png")).exists()


# --------------------------------------------------------------------------------------------- render


@pytest.mark.parametrize("name", sorted(SCENES))
def test_render_is_the_programs_png(name, tmp_path):
    """render() gives the values of the PNG the program writes for the same options: R, G, B, A, k / 255."""
    f = tmp_path / "p.png"
    assert program(*SCENES[name], "--size", "96x64", "-q", "-o", f)[0] == 0
    img, ref = instess.render(*SCENES[name], "--size", "96x64"), instess.read(f)
    assert img.channels == ref.channels == ("R", "G", "B", "A")
    assert img.pixels.shape == (64, 96, 4) and img.pixels.dtype == np.float32
    assert np.array_equal(img.pixels, ref.pixels)
    k = np.round(img.pixels * np.float32(255))  # every value is an 8-bit step k / 255, as the file stores it
    assert np.array_equal(img.pixels, k * np.float32(1 / 255))
    assert img.pixels.std() > 0  # something was drawn


def test_render_is_the_programs_exr(tmp_path):
    """format="exr": what the program's EXR holds, with the AOVs (infinite depth on the background), bit for bit."""
    args = ["--mesh", "icosahedron", "--size", "64x48", "--aov", "normal,instance,depth"]
    f = tmp_path / "p.exr"
    assert program(*args, "-q", "-o", f)[0] == 0
    img, ref = instess.render(*args, format="exr"), instess.read(f)
    assert img.channels == ref.channels
    assert img.channels[:5] == ("R", "G", "B", "A", "Z") and "depth" in img.channels
    assert np.array_equal(img.pixels, ref.pixels, equal_nan=True)
    assert np.isinf(img.channel("depth")).any() and np.isfinite(img.channel("depth")).any()


def test_render_errors_and_warnings():
    """A usage or input error raises with the program's message; what the call cannot do is refused; a level a
    grid cannot take is clamped with a warning, as the program warns on stderr."""
    with pytest.raises(instess.InstessError, match="one of: flat"):
        instess.render("--patch", "curvy")
    with pytest.raises(instess.InstessError, match="missing.obj"):
        instess.render("missing.obj")
    with pytest.raises(instess.InstessError, match="writes no file"):
        instess.render("-o", "x.png")
    with pytest.raises(instess.InstessError, match="exr"):
        instess.render("--aov", "normal")  # AOVs need format="exr", as they need an .exr file
    with pytest.warns(UserWarning, match="outside the range of --grid pg-fractional-odd"):
        img = instess.render("--grid", "pg-fractional-odd", "--level", "200", "--size", "32x32")
    assert img.width == 32


# --------------------------------------------------------------------------------------------- compare

FAILING = re.compile(r"failing pixels: (\d+)")


def test_compare_is_instess_compare(tmp_path):
    """compare()'s verdict, exit code and failing-pixel count are the program's, for the same files and
    thresholds: identical, different, within --fail, within --failpercent, other sizes, unreadable."""
    a, b, c = tmp_path / "a.png", tmp_path / "b.png", tmp_path / "c.png"
    assert program("--size", "64x64", "-q", "-o", a)[0] == 0
    img = instess.read(a)
    img.pixels[10, 20, 0] = 1.0 - img.pixels[10, 20, 0]  # one pixel far off
    img.pixels[30:32, 5:9, 2] += 3 / 255  # eight pixels a little off
    instess.write(img, b)
    assert program("--size", "64x32", "-q", "-o", c)[0] == 0
    # 9 of 4096 pixels differ (0.22 %): one by far, eight by 3/255
    cases = [(a, a, 0, 0), (a, b, 0, 0), (a, b, 0.02, 0), (a, b, 1.0, 0), (a, b, 0, 0.25), (a, b, 0, 0.2),
             (a, c, 0, 0), (a, tmp_path / "none.png", 0, 0)]
    verdicts = []
    for x, y, fail, pct in cases:
        r = instess.compare(x, y, fail=fail, failpercent=pct)
        code, out = program("compare", x, y, "--fail", fail, "--failpercent", pct)
        assert r.exit_code == code, (x, y, fail, pct, r)
        m = FAILING.search(out)
        if m:
            assert r.n_fail == int(m.group(1)), (r, out)
        verdicts.append(r.verdict)
    assert verdicts == ["pass", "different", "different", "pass", "pass", "different", "shape", "unreadable"]


def test_compare_numbers_and_diff_image(tmp_path):
    """On a difference: where and how large, and the diff image (failing pixel red) only then."""
    ref = instess.render("--size", "40x30")
    act = instess.Image(ref.pixels.copy(), ref.channels)
    act.pixels[7, 11, 1] += 0.25
    diff = tmp_path / "d.png"
    r = instess.compare(act, ref, diff=diff)
    assert not r and r.verdict == "different" and r.n_fail == 1 and r.n_pixels == 1200
    assert (r.max_x, r.max_y, r.max_channel) == (11, 7, 1) and abs(r.max_error - 0.25) < 1e-6
    d = instess.read(diff)
    assert tuple(d.pixels[7, 11]) == (1.0, 0.0, 0.0, 1.0)
    assert "0.25" in repr(r) and str(diff) in repr(r)
    assert instess.compare(ref, ref, diff=tmp_path / "none.png")
    assert not (tmp_path / "none.png").exists()
    nan = instess.Image(ref.pixels.copy(), ref.channels)
    nan.pixels[0, 0, 0] = np.nan  # a NaN against a number fails, at any threshold
    r = instess.compare(nan, ref, fail=1e30)
    assert not r and r.n_nonfinite == 1


# --------------------------------------------------------------------------------------------- files


def test_read_channels_of_an_exr(tmp_path):
    """An EXR's channels by name: the normals about unit length where the mesh is (interpolated across each drawn
    triangle), instance -1 on the background."""
    f = tmp_path / "n.exr"
    assert program("--mesh", "sphere", "--size", "48x48", "--aov", "normal,instance", "-q", "-o", f)[0] == 0
    ch = instess.read_channels(f)
    assert list(ch)[:5] == ["R", "G", "B", "A", "Z"] and {"N.X", "N.Y", "N.Z", "instance"} <= set(ch)
    inside = ch["instance"] >= 0
    assert inside.any() and (~inside).any() and (ch["instance"][~inside] == -1).all()
    length = np.sqrt(ch["N.X"] ** 2 + ch["N.Y"] ** 2 + ch["N.Z"] ** 2)
    assert np.allclose(length[inside], 1.0, atol=0.01)


def test_write_and_read_back(tmp_path):
    """write() then read(): a PNG keeps the first four channels as 8-bit values; an EXR keeps every channel."""
    img = instess.render("--size", "20x10", "--aov", "depth", format="exr")
    instess.write(img, tmp_path / "w.exr", description="from python")
    back = instess.read(tmp_path / "w.exr")
    assert back.channels == img.channels and np.array_equal(back.pixels, img.pixels, equal_nan=True)
    instess.write(img, tmp_path / "w.png")
    png = instess.read(tmp_path / "w.png")
    assert png.channels == ("R", "G", "B", "A")
    k = np.clip(np.floor(img.pixels[:, :, :4] * np.float32(255) + np.float32(0.5)), 0, 255)   # quantized as the file
    assert np.array_equal(png.pixels, k * np.float32(1 / 255))
    with pytest.raises(instess.InstessError, match="w.tif"):
        instess.write(img, tmp_path / "w.tif")


def test_one_process_many_renders():
    """A suite's worth of renders and comparisons in one process: the library is loaded once."""
    ref = instess.render("--size", "64x64")
    for level in range(1, 21):
        img = instess.render("--size", "64x64", "--level", str(level))
        assert instess.compare(img, img)
    assert instess.compare(instess.render("--size", "64x64"), ref)
