"""The Python module against the command line: the same library, the same numbers.

Run from ctest (tests/CMakeLists.txt) with PYTHONPATH=<build>/python and VOLSTREAM_BIN=<volstream>.
"""
import os
import resource
import subprocess
import sys

import numpy as np
import pytest

import volstream as vs

VOLSTREAM_BIN = os.environ.get("VOLSTREAM_BIN", "build/volstream")


def cli(*args):
    return subprocess.run([VOLSTREAM_BIN, *map(str, args)], check=True, capture_output=True, text=True).stdout


def read_pfm(path):
    """A colour or grey little/big-endian PFM as an (H, W, C) float32 array, rows top to bottom."""
    with open(path, "rb") as f:
        kind = f.readline().strip()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        channels = 3 if kind == b"PF" else 1
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4").astype(np.float32)
    return data.reshape(h, w, channels)[::-1]


@pytest.fixture(scope="module")
def dataset_dir(tmp_path_factory):
    d = tmp_path_factory.mktemp("py") / "jet"
    cli("demo", "jet", "--cells", 20000, "--steps", 2, "-o", d, "-q")
    return d


@pytest.fixture(scope="module")
def ds(dataset_dir):
    return vs.load(str(dataset_dir))


def cli_image(dataset_dir, tmp_path, *options):
    out = tmp_path / "cli.pfm"
    cli("render", dataset_dir, "--device", "cpu", "--alpha", "-o", out, "--size", "48x32", *options)
    rgb = read_pfm(out)
    alpha = read_pfm(tmp_path / "cli.alpha.pfm")
    return np.concatenate([rgb, alpha], axis=2)


def test_dataset_properties(ds, dataset_dir):
    assert ds.fields == ["pressure", "velocity", "vorticity"]
    assert list(ds.steps) == [0, 1]
    assert len(ds.times) == 2
    lo, hi = ds.domain
    assert len(lo) == 3 and all(a < b for a, b in zip(lo, hi))
    assert ds.domain_center == tuple((a + b) / 2 for a, b in zip(lo, hi))
    assert ds.cell_count > 10000
    assert ds.path == str(dataset_dir)
    assert "Dataset" in repr(ds)


def test_probe_equals_cli_and_brute_force(ds, dataset_dir, tmp_path):
    rng = np.random.default_rng(7)
    lo, hi = (np.array(v) for v in ds.domain)
    pts = lo + (hi - lo) * rng.random((200, 3))
    pts = np.vstack([pts, [hi + (hi - lo)]])  # far outside: NaN
    points_file = tmp_path / "points.txt"
    points_file.write_text("".join(f"{x!r} {y!r} {z!r}\n" for x, y, z in pts))
    for step in (0, 1):
        got = ds.probe("vorticity", pts, step=step)
        assert got.dtype == np.float32 and got.shape == (len(pts),)
        text = cli("probe", dataset_dir, "--field", "vorticity", "--step", step, "--points", points_file)
        want = np.array([float(v) for v in text.split()])
        assert np.isnan(got[-1]) and np.isnan(want[-1])
        np.testing.assert_allclose(got[:-1], want[:-1], rtol=1e-5)
        brute = ds.probe("vorticity", pts, step=step, brute_force=True)
        assert brute.dtype == np.float64 and np.isnan(brute[-1])
        np.testing.assert_allclose(got[:-1], brute[:-1], rtol=1e-5, atol=1e-5 * np.nanmax(np.abs(brute)))


def test_probe_bad_points(ds):
    with pytest.raises(ValueError):
        ds.probe("pressure", np.zeros((4, 2)))
    with pytest.raises(ValueError):
        ds.probe("pressure", np.zeros((1, 3)), step=5)


def test_probe_edge_cases(ds):
    assert ds.probe("pressure", np.zeros((0, 3))).shape == (0,)
    v = ds.probe("pressure", np.array([[np.nan, 0.0, 0.0], [0, 0, 0]], dtype=np.float32))  # converted to float64
    assert np.isnan(v[0]) and np.isfinite(v[1])
    assert ds.probe(None, [[0.0, 0.0, 0.0]])[0] == v[1]  # None: the first field; a list converts too


def test_threads_render_with_the_gil_released(ds):
    import threading

    scenes = [vs.create_scene(ds) for _ in range(3)]
    for sc in scenes:
        sc.camera.resolution = (64, 48)
    out = [None] * len(scenes)

    def work(i):
        out[i] = scenes[i].render()

    threads = [threading.Thread(target=work, args=(i,)) for i in range(len(scenes))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for img in out[1:]:
        np.testing.assert_array_equal(img, out[0])


def test_default_render_equals_cli(ds, dataset_dir, tmp_path):
    sc = vs.create_scene(ds)
    sc.camera.resolution = (48, 32)
    img = sc.render()
    assert img.shape == (32, 48, 4) and img.dtype == np.float32
    want = cli_image(dataset_dir, tmp_path)
    assert np.abs(img - want).max() <= 1e-6
    assert img[..., 3].max() > 0.1  # not an empty frame


def test_iso_render_equals_cli(ds, dataset_dir, tmp_path):
    sc = vs.create_scene(ds, field="pressure")
    sc.camera.resolution = (48, 32)
    sc.step = 1
    sc.iso = [50.0, 200.0]
    sc.transfer_function.cmap = "inferno"
    sc.transfer_function.set_bounds((-500.0, 500.0))
    img = sc.render()
    want = cli_image(dataset_dir, tmp_path, "--field", "pressure", "--step", 1, "--iso", "50,200", "--tf", "inferno",
                     "--range=-500,500")
    assert np.abs(img - want).max() <= 1e-6


def test_render_is_zero_copy(ds):
    sc = vs.create_scene(ds)
    sc.camera.resolution = (16, 8)
    a, b = sc.render(), sc.render()
    for img in (a, b):
        assert img.base is not None
        assert not img.flags.owndata
        assert img.flags.c_contiguous and img.flags.writeable
    assert a.ctypes.data != b.ctypes.data
    assert not np.shares_memory(a, b)
    np.testing.assert_array_equal(a, b)


def test_camera_round_trip(ds):
    sc = vs.create_scene(ds)
    cam = sc.camera
    default_pos = cam.position
    cam.position = (1.0, 2.0, 3.0)
    cam.focus = (4.0, 5.0, 6.0)
    cam.up = (0.0, 0.0, 1.0)
    cam.fov = 50
    cam.ortho = True
    cam.resolution = (40, 30)
    c = sc.camera  # a fresh view of the same scene
    assert c.position == (1.0, 2.0, 3.0)
    assert c.focus == (4.0, 5.0, 6.0)
    assert c.up == (0.0, 0.0, 1.0)
    assert c.fov == 50 and c.ortho
    assert c.resolution == (40, 30)
    c.reset()
    assert not c.ortho and c.fov == 35 and c.resolution == (40, 30)
    assert c.position != default_pos  # the default view is fitted to the new aspect ratio
    fresh = vs.create_scene(ds).camera
    fresh.resolution = (40, 30)
    assert c.position == fresh.position and c.focus == fresh.focus and c.up == fresh.up
    with pytest.raises(ValueError):
        c.fov = 180
    with pytest.raises(ValueError):
        c.resolution = (0, 10)
    c.position = c.focus  # degenerate: refused at render, not a crash
    with pytest.raises(ValueError):
        sc.render()


def test_transfer_function_round_trip(ds):
    sc = vs.create_scene(ds, field="pressure", log=False)
    tf = sc.transfer_function
    assert tf.cmap == "auto"
    lo, hi = ds.field_range("pressure", 0)
    assert tf.bounds == pytest.approx((lo, hi), rel=1e-6)
    tf.cmap = "viridis"
    tf.set_bounds((-10.0, 20.0))
    tf.log = False
    tf.set_opacity([(-10.0, 0.0), (20.0, 0.5)])
    t = sc.transfer_function
    assert t.cmap == "viridis"
    assert t.bounds == (-10.0, 20.0)
    assert t.opacity == [(-10.0, 0.0), (20.0, 0.5)]
    t.set_bounds(None)
    assert t.bounds == pytest.approx((lo, hi), rel=1e-6)
    sc.iso = [1.0, 2.0]
    assert sc.iso == [1.0, 2.0]
    sc.integrator = "blocks"
    assert sc.integrator == "blocks"
    sc.step = 1
    assert sc.step == 1
    sc.field = "velocity"
    assert sc.field == "velocity"


def test_bad_path_is_oserror(tmp_path):
    missing = str(tmp_path / "missing")
    with pytest.raises(OSError) as e:
        vs.load(missing)
    message = str(e.value)
    assert message.startswith(missing) and "\n" not in message
    # The same line the command line prints after "volstream: " (load converts what is not a dataset).
    r = subprocess.run([VOLSTREAM_BIN, "convert", missing, "-o", str(tmp_path / "out")], capture_output=True, text=True)
    assert r.returncode == 2 and r.stderr.strip() == "volstream: " + message
    (tmp_path / "damaged").mkdir()
    (tmp_path / "damaged" / "manifest.json").write_text("{")
    with pytest.raises(OSError) as e:
        vs.load(tmp_path / "damaged")  # a dataset's own error
    r = subprocess.run([VOLSTREAM_BIN, "info", tmp_path / "damaged"], capture_output=True, text=True)
    assert r.returncode == 2 and r.stderr.strip() == "volstream: " + str(e.value)


def test_bad_options_are_valueerror(ds):
    with pytest.raises(ValueError, match="no field 'nope'"):
        vs.create_scene(ds, field="nope")
    sc = vs.create_scene(ds)
    with pytest.raises(ValueError, match="unknown transfer function"):
        sc.transfer_function.cmap = "nope"
    assert sc.transfer_function.cmap == "auto"  # unchanged
    with pytest.raises(ValueError):
        sc.transfer_function.set_bounds((2.0, 1.0))
    with pytest.raises(ValueError):
        sc.step = 2
    with pytest.raises(ValueError):
        sc.integrator = "fast"
    with pytest.raises(ValueError):
        sc.iso = [float(i) for i in range(9)]
    with pytest.raises(ValueError):
        sc.save("frame.jpg")
    with pytest.raises(ValueError):
        vs.demo("nope")
    with pytest.raises(ValueError):
        vs.create_scene(ds, device="gpu")


def test_save_and_repr_png(ds, tmp_path):
    sc = vs.create_scene(ds)
    sc.camera.resolution = (24, 16)
    png = sc._repr_png_()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    sc.save(str(tmp_path / "a.png"))
    assert (tmp_path / "a.png").read_bytes() == png
    sc.save(str(tmp_path / "a.pfm"), background=(0, 0, 0))
    rgb = read_pfm(tmp_path / "a.pfm")
    np.testing.assert_allclose(rgb, sc.render()[..., :3], atol=1e-6)


def test_demo_temp_dir_removed():
    d = vs.demo("cosmo", cells=1e4, steps=1)
    path = d.path
    assert os.path.isdir(path) and d.fields == ["density", "temperature"]
    sc = vs.create_scene(d)
    sc.camera.resolution = (8, 8)
    sc.render()
    del d
    assert os.path.isdir(path)  # the scene keeps it alive
    del sc
    import gc

    gc.collect()
    assert not os.path.exists(os.path.dirname(path))


def test_steps_loop_memory_flat(ds):
    sc = vs.create_scene(ds)
    sc.camera.resolution = (512, 512)  # 4 MiB a frame

    def render_steps(n):
        for i in range(n):
            sc.step = ds.steps[i % len(ds.steps)]
            img = sc.render()
            assert img[..., 3].max() > 0
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss  # KiB

    after2 = render_steps(2)
    after10 = render_steps(10)
    assert after10 - after2 < 8 * 1024, (after2, after10)  # 8 frames kept would be 32 MiB


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, "-q"]))
