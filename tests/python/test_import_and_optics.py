"""The Python module's importers (load of what `volstream convert` takes, mesh demos), meshes in
datasets, probes and scenes, the transfer function helpers and the optics, against the command
line. Run like test_volstream.py (PYTHONPATH=<build>/python, VOLSTREAM_BIN=<volstream>)."""
import gc
import math
import os
import subprocess

import numpy as np
import pytest

import volstream as vs
from test_volstream import VOLSTREAM_BIN, cli, read_pfm


def cli_render(dataset_dir, out, *options):
    """The CLI's frame as (H, W, 4) premultiplied linear RGBA, 48x32 on the CPU."""
    cli("render", dataset_dir, "--device", "cpu", "--alpha", "-o", out, "--size", "48x32", *options)
    return np.concatenate([read_pfm(out), read_pfm(str(out)[: -len(".pfm")] + ".alpha.pfm")], axis=2)


def cli_probe(dataset_dir, field, pts, tmp_path):
    points_file = tmp_path / "points.txt"
    points_file.write_text("".join(f"{x!r} {y!r} {z!r}\n" for x, y, z in pts))
    return np.array([float(v) for v in cli("probe", dataset_dir, "--field", field, "--points", points_file).split()])


def random_points(ds, n=150, seed=3):
    lo, hi = (np.array(v) for v in ds.domain)
    return lo + (hi - lo) * np.random.default_rng(seed).random((n, 3))


# --- meshes ------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def mesh_files(tmp_path_factory):
    """A .vtu written by `volstream demo holes --write-mesh` and the CLI's conversion of it."""
    d = tmp_path_factory.mktemp("mesh")
    cli("demo", "holes", "--elements", 3000, "--steps", 1, "-o", d / "demo", "-q", "--write-mesh", d / "holes.vtu")
    cli("convert", d / "holes.vtu", "-o", d / "converted", "-q")
    return d / "holes.vtu", d / "converted"


def test_load_vtu_is_a_mesh_dataset(mesh_files):
    vtu, converted = mesh_files
    ds = vs.load(vtu)  # os.PathLike works too
    assert ds.kind == "mesh" and ds.cell_count is None
    assert ds.element_count > 1000 and ds.vertex_count > 100
    assert ds.fields == ["density", "linear"] and list(ds.steps) == [0] and len(ds.times) == 1
    assert vs.load(str(converted)).domain == ds.domain
    assert "elements" in repr(ds)
    path = ds.path
    assert os.path.isdir(path)  # a private temporary dataset, removed with the Dataset
    del ds
    gc.collect()
    assert not os.path.exists(path)


def test_load_joins_a_parallel_writers_pieces(mesh_files, tmp_path):
    """`demo --write-mesh NAME.pvtu` (four pieces with ghost cells) loads as the mesh it was cut
    from; so do VTK's own .pvtu and .vtm files of tests/data/vtu."""
    vtu, _ = mesh_files
    cli("demo", "holes", "--elements", 3000, "--steps", 1, "-o", tmp_path / "demo", "-q",
        "--write-mesh", tmp_path / "holes.pvtu")
    whole, pieces = vs.load(vtu), vs.load(tmp_path / "holes.pvtu")
    assert pieces.element_count == whole.element_count
    assert pieces.vertex_count < whole.vertex_count  # the joined mesh drops the points the holes left unused
    pts = random_points(whole)
    np.testing.assert_array_equal(pieces.probe("density", pts), whole.probe("density", pts))
    data = os.path.join(os.path.dirname(__file__), "..", "data", "vtu")
    for name in ("vtk_ghosts.pvtu", "vtk_blocks.vtm"):
        ds = vs.load(os.path.join(data, name))
        assert (ds.element_count, ds.vertex_count) == (135, 64) and "RTData" in ds.fields
    zone = vs.load(os.path.join(data, "vtk_blocks.vtm"), regions=["zone_0"])  # one block of the .vtm
    assert zone.element_count == 68


def test_load_ensight_case():
    """The EnSight Gold test cases of tests/data/ensight: ASCII and big-endian C Binary load as
    the same two-step mesh (polyhedra split, the boundary part left out)."""
    data = os.path.join(os.path.dirname(__file__), "..", "data", "ensight")
    ascii_case, binary_case = (vs.load(os.path.join(data, d, "mesh.case")) for d in ("ascii", "big_endian"))
    assert ascii_case.kind == "mesh" and ascii_case.element_count == 54 and len(ascii_case.steps) == 2
    assert {"f", "v", "cell"} <= set(ascii_case.fields)
    pts = np.array([[0.5, 0.5, 0.5], [2.5, 1.5, 1.0], [3.5, 0.5, 1.5]])
    np.testing.assert_allclose(ascii_case.probe("f", pts), 1 + pts @ [2, 3, 4], rtol=1e-5)
    np.testing.assert_allclose(binary_case.probe("f", pts), ascii_case.probe("f", pts), rtol=1e-6)


def test_load_quadratic_cells():
    """VTK's quadratic cells (tests/data/vtu/vtk_quadratic.vtu: one of each type, curved) load
    split into the linear elements of their nodes, with VTK's values at the nodes and the face
    and body centres (vtk_quadratic_probes.txt, less the pyramid's apex)."""
    data = os.path.join(os.path.dirname(__file__), "..", "data", "vtu")
    ds = vs.load(os.path.join(data, "vtk_quadratic.vtu"))
    assert (ds.element_count, ds.vertex_count) == (66, 159)
    rows = np.delete(np.loadtxt(os.path.join(data, "vtk_quadratic_probes.txt")), 131, axis=0)
    np.testing.assert_allclose(ds.probe("g", rows[:, :3]), rows[:, 3], rtol=1e-5, atol=1e-6)


def test_load_exodus_time_series():
    """An Exodus II file (tests/data/exodus/exodus_mixed.exo) loads with its three steps at their
    times, and step 1 probes as the .vtu VTK wrote of that step; the vector vel_x/y/z comes back
    as its magnitude and components."""
    data = os.path.join(os.path.dirname(__file__), "..", "data", "exodus")
    ds = vs.load(os.path.join(data, "exodus_mixed.exo"))
    assert (ds.element_count, list(ds.steps), list(ds.times)) == (120, [0, 1, 2], [0.0, 0.5, 1.25])
    assert {"g", "vel", "vel_x", "vel_y", "vel_z", "cell_id", "pressure"} <= set(ds.fields)
    vtu = vs.load(os.path.join(data, "exodus_mixed_1.vtu"))
    pts = random_points(vtu)
    for field in ("g", "vel_y"):
        np.testing.assert_allclose(ds.probe(field, pts, step=1), vtu.probe(field, pts), rtol=1e-5, atol=1e-6)


def test_load_cgns_zones_and_steps():
    """A CGNS file (tests/data/cgns/cgns_mixed.cgns: an unstructured and a structured zone, three
    steps) loads joined, and step 1 probes as the .vtu VTK wrote of that step."""
    data = os.path.join(os.path.dirname(__file__), "..", "data", "cgns")
    ds = vs.load(os.path.join(data, "cgns_mixed.cgns"))
    assert (ds.element_count, list(ds.times)) == (144, [0.0, 0.5, 1.25])
    vtu = vs.load(os.path.join(data, "cgns_mixed_1.vtu"))
    pts = random_points(vtu)
    np.testing.assert_allclose(ds.probe("g", pts, step=1), vtu.probe("g", pts), rtol=1e-5, atol=1e-6)


def test_load_openfoam_regions():
    """A multi-region OpenFOAM case (tests/data/openfoam/box_regions: fluid and solid, the solid
    without U) loads its regions joined, or those asked for by regions=; U is NaN in the solid."""
    case = os.path.join(os.path.dirname(__file__), "..", "data", "openfoam", "box_regions")
    both, fluid = vs.load(case), vs.load(case, regions=["fluid"])
    assert (both.element_count, list(both.times)) == (964, [0.0, 0.1, 0.2])
    solid_point, fluid_point = (0.3, 0.5, 0.4), (1.0, 0.5, 0.4)
    u = both.probe("U", [solid_point, fluid_point], step=2)
    assert math.isnan(u[0]) and not math.isnan(u[1])
    assert fluid.probe("U", [fluid_point], step=2)[0] == u[1]
    with pytest.raises(OSError, match="no region 'gas'"):
        vs.load(case, regions=["gas"])


def test_load_gmsh_physical_groups():
    """Gmsh's physical groups of volumes (tests/data/gmsh/gmsh_groups_22.msh, MSH 2.2, which
    writes an element once per group holding it) by name or number, as regions=."""
    msh = os.path.join(os.path.dirname(__file__), "..", "data", "gmsh", "gmsh_groups_22.msh")
    assert vs.load(msh).element_count == 177
    assert vs.load(msh, regions=["top", "8"]).element_count == 169
    with pytest.raises(OSError, match="no physical group 'bottom' of volume elements"):
        vs.load(msh, regions=["bottom"])


def test_mesh_probe_equals_cli_and_brute_force(mesh_files, tmp_path):
    vtu, converted = mesh_files
    ds = vs.load(str(vtu))
    pts = random_points(ds)
    got = ds.probe("density", pts)
    want = cli_probe(converted, "density", pts, tmp_path)
    np.testing.assert_array_equal(np.isnan(got), np.isnan(want))
    assert np.isnan(got).any() and not np.isnan(got).all()  # the holes: NaN inside the box
    np.testing.assert_allclose(got, want, rtol=1e-5)
    brute = ds.probe("density", pts, brute_force=True)
    assert brute.dtype == np.float64
    np.testing.assert_array_equal(np.isnan(brute), np.isnan(got))
    ok = ~np.isnan(got)
    np.testing.assert_allclose(got[ok], brute[ok], rtol=1e-4, atol=1e-5 * np.nanmax(np.abs(brute)))


def test_mesh_render_equals_cli(mesh_files, tmp_path):
    vtu, converted = mesh_files
    sc = vs.create_scene(vs.load(vtu), field="density")
    sc.camera.resolution = (48, 32)
    img = sc.render()
    want = cli_render(converted, tmp_path / "cli.pfm", "--field", "density")
    assert np.abs(img - want).max() <= 1e-6
    assert img[..., 3].max() > 0.05


def test_mesh_demo():
    ds = vs.demo("tets", elements=2000, steps=2)
    assert ds.kind == "mesh" and list(ds.steps) == [0, 1]
    assert 1500 < ds.element_count < 2500
    sc = vs.create_scene(ds)
    sc.camera.resolution = (16, 16)
    sc.step = 1
    assert sc.render()[..., 3].max() > 0
    with pytest.raises(ValueError):
        vs.demo("tets", elements=1)


def test_mesh_encodings_probe_the_same():
    compact = vs.demo("mixed", elements=3000, steps=1)
    reference = vs.demo("mixed", elements=3000, steps=1, encoding="reference")
    pts = random_points(compact)
    got, want = compact.probe("density", pts), reference.probe("density", pts)
    np.testing.assert_array_equal(np.isnan(got), np.isnan(want))
    assert not np.isnan(got).all()
    np.testing.assert_allclose(got, want, rtol=1e-5, atol=1e-6)  # paired tets round differently
    with pytest.raises(ValueError):
        vs.demo("tets", elements=2000, encoding="stored")


def test_mesh_split_into_tets_keeps_the_linear_field():
    exact = vs.demo("mixed", elements=3000, steps=1)
    split = vs.demo("mixed", elements=3000, steps=1, split_into_tets=True)
    assert split.element_count > 2 * exact.element_count  # 2, 3 and 6 tets per element
    pts = random_points(exact, n=2000)
    got, want = split.probe("linear", pts), exact.probe("linear", pts)
    both = ~np.isnan(got) & ~np.isnan(want)
    assert both.sum() > 500
    assert (np.isnan(got) != np.isnan(want)).sum() < 0.01 * len(pts)  # the curved sides cut flat
    np.testing.assert_allclose(got[both], want[both], rtol=1e-5, atol=1e-5)
    with pytest.raises(ValueError):
        vs.demo("jet", cells=1e4, split_into_tets=True)


# --- AMReX plotfiles ---------------------------------------------------------------------------


def test_load_plotfile_probe_equals_cli_and_brute_force(tmp_path):
    """A two-level plotfile (written by the C++ writer, tests/python/write_plotfile.cpp): load's
    probes equal `volstream convert` + `volstream probe`, and the tent-basis brute force."""
    writer = os.environ.get("VOLSTREAM_TEST_PLOTFILE")
    if not writer:
        pytest.skip("VOLSTREAM_TEST_PLOTFILE (the plotfile writer) is not set")
    plt = tmp_path / "plt00000"
    subprocess.run([writer, plt], check=True)
    ds = vs.load(plt)
    assert ds.kind == "amr" and ds.fields == ["density", "temperature"]
    assert ds.domain == ((0.0, 0.0, 0.0), (2.0, 1.0, 1.0))
    cli("convert", plt, "-o", tmp_path / "cli", "-q")
    pts = random_points(ds, n=400)
    for field in ds.fields:
        got = ds.probe(field, pts)
        np.testing.assert_allclose(got, cli_probe(tmp_path / "cli", field, pts, tmp_path), rtol=1e-6)
        np.testing.assert_allclose(got, ds.probe(field, pts, brute_force=True), rtol=1e-5)


# --- raw grids and ExaBrick ---------------------------------------------------------------------


def test_load_raw_grid_equals_cli(tmp_path):
    dims = (6, 5, 4)
    values = np.arange(np.prod(dims), dtype=np.float32).reshape(dims[::-1])  # x fastest
    raw = tmp_path / "grid.raw"
    values.tofile(raw)
    ds = vs.load(str(raw), dims=dims, field="rho", origin=(1.0, 0.0, 0.0), spacing=(0.5, 0.5, 0.5))
    assert ds.kind == "amr" and ds.fields == ["rho"] and ds.cell_count == values.size
    assert ds.domain == ((1.0, 0.0, 0.0), (4.0, 2.5, 2.0))
    # Cell centres: the tent basis gives each cell its own value there.
    k, j, i = np.meshgrid(*(np.arange(n) for n in dims[::-1]), indexing="ij")
    centres = np.stack([1.0 + 0.5 * (i + 0.5), 0.5 * (j + 0.5), 0.5 * (k + 0.5)], axis=-1).reshape(-1, 3)
    np.testing.assert_allclose(ds.probe("rho", centres), values.reshape(-1), rtol=1e-6)
    cli("convert", raw, "--dims", "6,5,4", "--field", "rho", "--origin", "1,0,0", "--spacing", "0.5,0.5,0.5", "-o",
        tmp_path / "cli", "-q")
    pts = random_points(ds)
    np.testing.assert_allclose(ds.probe("rho", pts), cli_probe(tmp_path / "cli", "rho", pts, tmp_path), rtol=1e-6)


def test_load_exabrick(tmp_path):
    # Two levels: a coarse 2^3 block of width-2 cells (level 1) beside 8 fine cells (level 0).
    cells = [(x, y, z, 1) for z in (0, 2) for y in (0, 2) for x in (4, 6)]
    cells += [(x, y, z, 0) for z in (0, 1) for y in (0, 1) for x in (0, 1)]
    np.array(cells, dtype="<i4").tofile(tmp_path / "data.cells")
    density = np.linspace(1, 2, len(cells), dtype="<f4")
    density.tofile(tmp_path / "density.scalars")
    (density * 3).tofile(tmp_path / "pressure.scalars")
    ds = vs.load([tmp_path / "data.cells", tmp_path / "density.scalars", tmp_path / "pressure.scalars"])
    assert ds.fields == ["density", "pressure"] and ds.cell_count == len(cells)
    lo, hi = ds.field_range("pressure")
    assert (lo, hi) == pytest.approx((3.0, 6.0))
    one = vs.load([tmp_path / "data.cells", tmp_path / "density.scalars"], fields=["density"])
    assert one.fields == ["density"]


# --- errors -------------------------------------------------------------------------------------


def test_load_errors_are_the_cli_lines(tmp_path):
    missing = str(tmp_path / "missing.vtu")
    with pytest.raises(OSError) as e:
        vs.load(missing)
    r = subprocess.run([VOLSTREAM_BIN, "convert", missing, "-o", tmp_path / "out"], capture_output=True, text=True)
    assert r.returncode == 2 and r.stderr.strip() == "volstream: " + str(e.value)
    bad = tmp_path / "bad.vtu"
    bad.write_text("<VTKFile type='UnstructuredGrid'>")
    with pytest.raises(OSError) as e:
        vs.load(bad)
    assert str(e.value).startswith(str(bad)) and "\n" not in str(e.value)
    (tmp_path / "grid.raw").write_bytes(b"\0" * 8)
    with pytest.raises(ValueError, match="dims"):
        vs.load(tmp_path / "grid.raw")
    with pytest.raises(ValueError):
        vs.load(tmp_path / "grid.raw", dims=(2, 2, 2), type="float16")
    assert not [p for p in os.listdir(tmp_path) if p.startswith("volstream_python")]


# --- transfer function helpers ------------------------------------------------------------------


@pytest.fixture(scope="module")
def jet_dir(tmp_path_factory):
    d = tmp_path_factory.mktemp("jet") / "jet"
    cli("demo", "jet", "--cells", 20000, "--steps", 1, "-o", d, "-q")
    return d


def test_add_gaussian_points(jet_dir):
    sc = vs.create_scene(vs.load(jet_dir), field="pressure")
    tf = sc.transfer_function
    tf.set_bounds((0.0, 100.0))
    tf.add_gaussian(50.0, 8.0, 0.4)  # standard deviation sqrt(8 / 2) = 2
    pts = tf.opacity
    assert len(pts) == 17
    xs, alphas = np.array(pts).T
    np.testing.assert_allclose(xs, 50.0 + 2.0 * np.arange(-8, 9) / 2)
    np.testing.assert_allclose(alphas[1:-1], 0.4 * np.exp(-((xs[1:-1] - 50.0) ** 2) / 8.0))
    assert alphas[0] == alphas[-1] == 0.0 and alphas[8] == pytest.approx(0.4)
    tf.add_gaussian(50.0, 8.0, 0.8)  # summed at the same points, clamped to 1
    assert len(tf.opacity) == 17 and tf.opacity[8][1] == 1.0
    with pytest.raises(ValueError):
        tf.add_gaussian(50.0, 0.0, 0.5)
    assert len(tf.opacity) == 17  # unchanged


def test_add_gaussian_log_scale(jet_dir):
    sc = vs.create_scene(vs.load(jet_dir), field="pressure")
    tf = sc.transfer_function
    tf.set_bounds((1.0, 1000.0))
    tf.log = True
    tf.add_gaussian(10.0, 0.02, 0.5)  # in decades: centre 1, standard deviation 0.1
    xs, alphas = np.array(tf.opacity).T
    np.testing.assert_allclose(np.log10(xs), 1.0 + 0.1 * np.arange(-8, 9) / 2, atol=1e-12)
    assert alphas[8] == pytest.approx(0.5)
    with pytest.raises(ValueError):
        tf.add_gaussian(-1.0, 0.02, 0.5)


def test_add_layers_points(jet_dir):
    sc = vs.create_scene(vs.load(jet_dir), field="pressure")
    tf = sc.transfer_function
    tf.set_bounds((0.0, 100.0))
    tf.add_layers(3, alpha=0.5)
    xs, alphas = np.array(tf.opacity).T
    assert len(xs) == 3 * 17 and np.all(np.diff(xs) > 0)
    sigma = math.sqrt(0.001 * 100.0**2 / 3 / 2)  # default width 0.001 * span^2 / n
    for i, c in enumerate((0.0, 50.0, 100.0)):
        np.testing.assert_allclose(xs[17 * i : 17 * (i + 1)], c + sigma * np.arange(-8, 9) / 2)
        assert alphas[17 * i + 8] == pytest.approx(0.5)
    tf.set_opacity([])
    tf.add_layers(4, w=1.0)  # yt's default alphas: logspace(-3, 0, n)
    peaks = [a for x, a in tf.opacity if any(abs(x - c) < 1e-9 for c in np.linspace(0, 100, 4))]
    np.testing.assert_allclose(peaks, np.logspace(-3, 0, 4))
    img = sc.render()
    assert img[..., 3].max() > 0
    with pytest.raises(ValueError):
        tf.add_layers(2, alpha=[0.1])


# --- optics -------------------------------------------------------------------------------------


def test_blackbody_equals_cli(tmp_path):
    d = tmp_path / "cosmo"
    cli("demo", "cosmo", "--cells", 10000, "--steps", 1, "-o", d, "-q")
    sc = vs.create_scene(vs.load(d))
    sc.camera.resolution = (48, 32)
    sc.optics = "blackbody"
    assert sc.integrator == "auto" and sc.temperature_field == "temperature"
    img = sc.render()
    want = cli_render(d, tmp_path / "cli.pfm", "--optics", "blackbody")
    assert np.abs(img - want).max() <= 1e-6
    assert img[..., 3].max() > 0
    with pytest.raises(ValueError):
        sc.optics = "xray"
    with pytest.raises(ValueError):
        sc.temperature_field = "nope"


def test_color_field_equals_cli(jet_dir, tmp_path):
    ds = vs.load(jet_dir)
    sc = vs.create_scene(ds, field="pressure")
    sc.camera.resolution = (48, 32)
    iso = float(np.float32(np.mean(ds.field_range("pressure"))))
    sc.iso = [iso]
    sc.transfer_function.set_opacity([(iso, 0.0)])  # no volume in front of the surface
    sc.color_field = "velocity"
    assert sc.color_field == "velocity"
    img = sc.render()
    want = cli_render(jet_dir, tmp_path / "cli.pfm", "--field", "pressure", "--iso", repr(iso), "--color-field",
                      "velocity", f"--opacity={iso!r}:0")
    assert np.abs(img - want).max() <= 1e-6
    assert img[..., 3].max() > 0.1  # the surface is there
    sc.color_field = None
    assert np.abs(sc.render() - img).max() > 0  # coloured by pressure again
