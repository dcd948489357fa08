"""Off-screen pictures of a run with pyvista: plan and 3-D snapshots, a GIF of the pounding window.

:func:`render` takes a :class:`~pounding.framework.engine.results.Result` (with its
scene for the frames and walls; without it only the slabs are drawn) or a run
directory holding ``response.npz`` (``t``, ``<B>_cm`` (nt, storeys, 3) and
``<B>_vertices`` for every building B) and ``scene.toml``. It writes

* ``render_plan.png`` - plan view (parallel projection) at the key instant;
* ``render_3d.png`` - 3-D view at the same instant;
* ``render_pounding.gif`` - the pounding window: from 0.5 s before the first
  contact to 0.5 s after the last, at most ``max_frames`` frames.

The key instant is the output step nearest the start of the contact with the
largest impulse (an impact, or a force law's contact episode: the contacts of a
Result); without them, the step where a pair is closest. Contacts are found from the log, else from the geometry
(signed gap <= max(contact tolerance, 1 mm) at an output step). Displacements
are magnified ``magnify`` times; the rest gap is not, so slabs that touch
appear to overlap. Slabs of a pair in contact are drawn red. With the scene,
retaining walls are drawn as their faces standing from the ground to their top
(grey, fixed) and links between slabs as lines between their attachment points,
moving with the slabs (the ParaView series' parts, :mod:`pounding.io.vtk`).

Headless machines: rendering needs an OpenGL context without a display. VTK's
wheels pick one at run time: X (needs $DISPLAY), EGL (Debian packages
``libegl1`` and ``libgl1-mesa-dri``: Mesa's software rasteriser through EGL)
or OSMesa (``libosmesa6``). A failed context creation crashes the process
(segfault) rather than raising, so :func:`check_offscreen` first tries each
in a subprocess, then fixes the working one for this process through
``VTK_DEFAULT_OPENGL_WINDOW``; when none works it raises
:class:`RenderUnavailable` naming what is missing.
"""

from __future__ import annotations

import ctypes.util
import os
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from pounding.io.vtk import LINE, PANEL, SLAB, Drawing, LinkDrawing, Motion, wall_grid

WINDOWS = {
    "vtkXOpenGLRenderWindow": "X",
    "vtkEGLRenderWindow": "EGL",
    "vtkOSOpenGLRenderWindow": "OSMesa",
}

_PROBE = r"""
from vtkmodules.vtkRenderingCore import vtkRenderWindow, vtkRenderer
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
rw = vtkRenderWindow()
rw.SetOffScreenRendering(1)
rw.SetSize(8, 8)
rw.AddRenderer(vtkRenderer())
rw.Render()
print("PROBE", rw.GetClassName(), int(rw.SupportsOpenGL()))
"""

_backend: str | None = None  # the render window class that works in this process
_failure: str | None = None

BUILDING_RGB = [(70, 130, 200), (240, 150, 60), (90, 170, 90), (150, 110, 190)]
CONTACT_RGB = (220, 30, 30)
#: fixed retaining walls, and links between slabs
WALL_RGB = "#8c8c8c"
LINK_RGB = "#202020"
NEAR_CONTACT = 1e-3  # [m] without an impact log, slabs closer than this at an output step are drawn in contact


class RenderUnavailable(RuntimeError):
    """Off-screen rendering cannot run here (no pyvista, or no OpenGL context without a display)."""


# =============================================================================
# Off-screen check
# =============================================================================


def _probe(window: str | None, timeout: float = 120.0) -> tuple[bool, str]:
    env = dict(os.environ)
    env.pop("VTK_DEFAULT_OPENGL_WINDOW", None)
    if window:
        env["VTK_DEFAULT_OPENGL_WINDOW"] = window
    try:
        cp = subprocess.run([sys.executable, "-c", _PROBE], env=env, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return False, "timed out"
    for line in cp.stdout.splitlines():
        if line.startswith("PROBE "):
            _, cls, ok = line.split()
            if ok == "1":
                return True, cls
    return False, f"exit code {cp.returncode}"


def _missing_message() -> str:
    have = {lib: ctypes.util.find_library(lib) for lib in ("EGL", "OSMesa", "GL")}
    missing = []
    if not have["EGL"]:
        missing.append("libEGL.so.1 (Debian package libegl1)")
    if not have["OSMesa"]:
        missing.append("libOSMesa.so (libosmesa6)")
    if not os.environ.get("DISPLAY"):
        missing.append("an X display ($DISPLAY unset; xvfb-run would provide one)")
    found = ", ".join(f"lib{k}" for k, v in have.items() if v)
    hint = "install libegl1 and libgl1-mesa-dri, or libosmesa6, with apt-get; or run under xvfb-run"
    what = "; missing " + ", ".join(missing) if missing else f"; found {found} but no context could be created (Mesa driver libgl1-mesa-dri missing?)"
    return f"off-screen rendering unavailable: VTK could not create an OpenGL context{what} - {hint}"


def check_offscreen() -> str:
    """Make sure pyvista can render off-screen here; returns the VTK render window class used.

    Raises
    ------
    RenderUnavailable
        One line naming what is missing (pyvista, or the system OpenGL libraries).
    """
    global _backend, _failure
    if _backend is not None:
        return _backend
    if _failure is not None:
        raise RenderUnavailable(_failure)
    try:
        import pyvista  # noqa: F401
        import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
    except ImportError as exc:  # pragma: no cover - depends on the environment
        _failure = f"off-screen rendering unavailable: {exc.name or 'pyvista'} is not installed (pip install pyvista)"
        raise RenderUnavailable(_failure) from exc
    except OSError as exc:  # pragma: no cover - a system library the VTK wheel links against is missing
        _failure = f"off-screen rendering unavailable: VTK does not load ({exc}); on Debian install libgl1 and libxrender1"
        raise RenderUnavailable(_failure) from exc
    user = os.environ.get("VTK_DEFAULT_OPENGL_WINDOW")
    if user:
        candidates = [user]
    elif os.environ.get("DISPLAY"):
        candidates = [None, "vtkEGLRenderWindow", "vtkOSOpenGLRenderWindow"]
    else:
        candidates = ["vtkEGLRenderWindow", "vtkOSOpenGLRenderWindow"]
    for cand in candidates:
        ok, cls = _probe(cand)
        if ok:
            if cand and not user:
                os.environ["VTK_DEFAULT_OPENGL_WINDOW"] = cand
            _backend = cls
            return cls
    _failure = _missing_message()
    raise RenderUnavailable(_failure)


# =============================================================================
# Input
# =============================================================================


def load_run(run_dir) -> tuple:
    """(scene, Motion) of a run directory holding ``response.npz`` and ``scene.toml``."""
    from pounding.errors import InputError
    from pounding.io.scene import load_scene

    run_dir = Path(run_dir)
    npz, toml = run_dir / "response.npz", run_dir / "scene.toml"
    for f in (npz, toml):
        if not f.is_file():
            raise InputError(f"{f.name} not found in the run directory", file=str(run_dir))
    scene = load_scene(toml)
    with np.load(npz) as data:
        if "t" not in data:
            raise InputError("no 't' array", file=str(npz))
        cm = {}
        for b in scene.buildings:
            key = f"{b.name}_cm"
            if key not in data:
                raise InputError(f"no {key!r} array (the scene's building {b.name!r})", file=str(npz))
            cm[b.name] = data[key]
            if cm[b.name].shape[1:] != (b.n_storeys, 3):
                raise InputError(f"{key} has shape {cm[b.name].shape}, expected (nt, {b.n_storeys}, 3)", file=str(npz))
        t = data["t"]
    return scene, Motion.from_arrays(scene, t, cm)


def _slabs_only(result):
    """A scene stand-in drawing a Result's slabs only (no elements)."""
    bs = {n: SimpleNamespace(name=n, slabs=tuple(s.slabs), elements=()) for n, s in zip(result.names, result.systems)}
    return SimpleNamespace(building=lambda name: bs[name], buildings=tuple(bs.values()))


# =============================================================================
# Choosing frames
# =============================================================================


def pounding_window(motion: Motion, *, margin: float = 0.5, gaps: np.ndarray | None = None) -> tuple[int, int, int]:
    """(first, last, key) output indices of the pounding window and its key instant (see the module docstring)."""
    t = motion.t
    nt = len(t)
    if motion.episodes or motion.impacts:  # the contacts of every law: impacts, and force laws' episodes
        spans = [(e.start, e.end, e.impulse) for e in motion.episodes] or [(i.time, i.time, i.impulse) for i in motion.impacts]
        t0, t1 = min(s[0] for s in spans), max(s[1] for s in spans)
        big = max(spans, key=lambda s: s[2])
        key = int(np.argmin(np.abs(t - big[0])))
    elif motion.pairs:
        g = motion.pair_gaps() if gaps is None else gaps
        gmin = g.min(axis=1)
        touching = np.flatnonzero(gmin <= max(motion.tolerance, 1e-3))
        key = int(np.argmin(gmin))
        t0, t1 = (float(t[touching[0]]), float(t[touching[-1]])) if touching.size else (float(t[key]), float(t[key]))
    else:
        peak = np.zeros(nt)
        for c in motion.cm:
            peak = np.maximum(peak, np.max(np.hypot(c[..., 0], c[..., 1]), axis=1))
        key = int(np.argmax(peak))
        t0 = t1 = float(t[key])
    first = int(np.searchsorted(t, t0 - margin, side="left"))
    last = int(np.searchsorted(t, t1 + margin, side="right")) - 1
    return max(first, 0), min(max(last, first), nt - 1), key


# =============================================================================
# Rendering
# =============================================================================


class _Scene3D:
    """The pyvista meshes of a drawing, updated in place frame by frame."""

    def __init__(self, pv, drawing: Drawing, motion: Motion, magnify: float, scene=None):
        self.pv, self.d, self.m, self.magnify = pv, drawing, motion, magnify
        walls, links = getattr(scene, "walls", ()), getattr(scene, "links", ())
        self.walls = pv.wrap(wall_grid(walls)) if walls else None  # fixed: drawn once
        self.link_drawing = LinkDrawing.build(scene, motion.names, {}) if links else None
        self.links = None
        if self.link_drawing is not None:
            n = len(self.link_drawing.ends)
            self.links = pv.PolyData(self.link_drawing.points.reshape(-1, 3).copy(),
                                     lines=np.array([x for i in range(n) for x in (2, 2 * i, 2 * i + 1)], dtype=np.int64))
        cells = drawing.cells
        kind = drawing.cell_kind

        def faces(sel):
            return np.array([x for i in sel for x in (len(cells[i]), *cells[i])], dtype=np.int64)

        self.slab_ids = np.flatnonzero(kind == SLAB)
        line_ids = np.flatnonzero(kind == LINE)
        panel_ids = np.flatnonzero(kind == PANEL)
        pts = drawing.points.copy()
        self.slabs = pv.PolyData(pts.copy(), faces=faces(self.slab_ids))
        self.rest = pv.PolyData(pts.copy(), faces=faces(self.slab_ids))
        self.lines = pv.PolyData(pts.copy(), lines=faces(line_ids)) if line_ids.size else None
        self.panels = pv.PolyData(pts.copy(), faces=faces(panel_ids)) if panel_ids.size else None
        self.base_rgb = np.array([BUILDING_RGB[b % len(BUILDING_RGB)] for b in drawing.cell_building[self.slab_ids]], dtype=np.uint8)
        self.slabs.cell_data["rgb"] = self.base_rgb.copy()
        if self.lines is not None:
            self.lines.cell_data["rgb"] = (0.6 * np.array([BUILDING_RGB[b % len(BUILDING_RGB)] for b in drawing.cell_building[line_ids]])).astype(np.uint8)
        if self.panels is not None:
            self.panels.cell_data["rgb"] = (0.5 * np.array([BUILDING_RGB[b % len(BUILDING_RGB)] for b in drawing.cell_building[panel_ids]]) + 100).astype(np.uint8)

    def _touching(self, k: int, cm) -> np.ndarray:
        """in_contact flags (cells) at output step k: geometry, plus impacts logged within half a step of it."""
        m = self.m
        tol = m.tolerance if m.impacts else max(m.tolerance, NEAR_CONTACT)
        flag, _ = self.d.contact(m.slabs, cm, m.pairs, tol)
        if m.impacts:
            t = m.t
            lo = 0.5 * (t[k - 1] + t[k]) if k > 0 else -np.inf
            hi = 0.5 * (t[k] + t[k + 1]) if k + 1 < len(t) else np.inf
            for p in {i.pair for i in m.impacts if lo < i.time <= hi}:
                a, fa, b, fb, _ = m.pairs[p]
                for key in ((a, fa), (b, fb)):
                    if key in self.d.slab_cell:
                        flag[self.d.slab_cell[key]] = 1
        return flag

    def update(self, k: int) -> None:
        cm = [c[k] for c in self.m.cm]
        disp = self.d.displacement(self.m.slabs, cm)
        pts = self.d.points + self.magnify * disp
        for mesh in (self.slabs, self.lines, self.panels):
            if mesh is not None:
                mesh.points = pts.copy()
        if self.links is not None:
            ld = self.link_drawing
            self.links.points = (ld.points + self.magnify * ld.displacement(self.m.slabs, cm)).reshape(-1, 3)
        flag = self._touching(k, cm)
        rgb = self.base_rgb.copy()
        rgb[flag[self.slab_ids] == 1] = CONTACT_RGB
        self.slabs.cell_data["rgb"] = rgb

    def add_to(self, plotter, plan: bool = False) -> None:
        plotter.add_mesh(self.rest, style="wireframe", color="grey", line_width=1, opacity=0.5)
        if self.walls is not None:  # from above a wall is its face line: drawn as lines there
            style = dict(style="wireframe", line_width=3) if plan else dict(opacity=0.45, show_edges=True, edge_color="black")
            plotter.add_mesh(self.walls, color=WALL_RGB, **style)
        if self.links is not None:
            plotter.add_mesh(self.links, color=LINK_RGB, line_width=4)
        if plan:  # outlines of every storey; the slabs in contact filled (the top slabs would hide them)
            plotter.add_mesh(self.slabs, scalars="rgb", rgb=True, style="wireframe", line_width=2)
            hit = np.flatnonzero(np.all(self.slabs.cell_data["rgb"] == CONTACT_RGB, axis=1))
            if hit.size:
                plotter.add_mesh(self.slabs.extract_cells(hit), color=tuple(c / 255 for c in CONTACT_RGB), opacity=0.45)
            return
        plotter.add_mesh(self.slabs, scalars="rgb", rgb=True, opacity=0.85, show_edges=True, edge_color="black", line_width=1.5)
        if self.panels is not None:
            plotter.add_mesh(self.panels, scalars="rgb", rgb=True, opacity=0.6)
        if self.lines is not None:
            plotter.add_mesh(self.lines, scalars="rgb", rgb=True, line_width=2)

    def caption(self, k: int) -> str:
        return f"t = {self.m.t[k]:.3f} s    displacements x{self.magnify:g} (gap not magnified)    red: slabs in contact"


def _plotter(pv, size, view: str, sc: _Scene3D):
    p = pv.Plotter(off_screen=True, window_size=list(size))
    p.set_background("white")
    sc.add_to(p, plan=view == "plan")
    labels = [[n, tuple(c / 255 for c in BUILDING_RGB[i % len(BUILDING_RGB)])] for i, n in enumerate(sc.m.names)]
    labels.append(["in contact", tuple(c / 255 for c in CONTACT_RGB)])
    p.add_legend(labels=labels, bcolor="white", border=True, face="rectangle", loc="upper right", size=(0.14, 0.035 * len(labels)))
    every = sc.d.points if sc.walls is None else np.vstack([sc.d.points, np.asarray(sc.walls.points)])
    lo, hi = every.min(axis=0), every.max(axis=0)
    c = 0.5 * (lo + hi)
    if view == "plan":
        p.view_xy()
        p.enable_parallel_projection()
        p.reset_camera()
        dx, dy = float(hi[0] - lo[0]), float(hi[1] - lo[1])
        p.camera.parallel_scale = 0.5 * max(dy, dx * size[1] / size[0]) * 1.25 + 1e-9
    else:
        span = float(np.linalg.norm(hi - lo)) or 1.0
        p.camera_position = [tuple(c + span * np.array([0.55, -1.2, 0.7])), tuple(c), (0.0, 0.0, 1.0)]
        p.reset_camera()
        p.camera.zoom(1.25)
    return p


def render(run_dir_or_result, out_dir, *, magnify: float = 50.0, scene=None, fps: float = 10.0, max_frames: int = 80, window_size=(1200, 800), gif_size=(800, 540), margin: float = 0.5) -> list[Path]:
    """Render snapshots and a GIF of the pounding window (see the module docstring).

    Parameters
    ----------
    run_dir_or_result : Result or path
        A Result, or a directory with ``response.npz`` and ``scene.toml``.
    out_dir : path
        Created if missing.
    magnify : float
        Displacement magnification.
    scene : Scene, optional
        With a Result: draws its frames and walls (without it only slabs).
    fps : float
        GIF frame rate.
    max_frames : int
        At most this many GIF frames (output steps of the window, evenly thinned).
    window_size : (int, int)
        Pixels of the snapshots.
    gif_size : (int, int)
        Pixels of the GIF frames.
    margin : float
        Seconds shown before the first and after the last contact.

    Returns
    -------
    list of Path
        ``render_plan.png``, ``render_3d.png``, ``render_pounding.gif``.

    Raises
    ------
    RenderUnavailable
        Off-screen rendering is not possible here.
    """
    check_offscreen()
    import pyvista as pv

    if isinstance(run_dir_or_result, (str, os.PathLike)):
        scene, motion = load_run(run_dir_or_result)
    else:
        motion = Motion.from_result(run_dir_or_result, scene)
        if scene is None:
            scene = _slabs_only(run_dir_or_result)
    drawing = Drawing.build(scene, motion.names)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    first, last, key = pounding_window(motion, margin=margin)
    sc = _Scene3D(pv, drawing, motion, magnify, scene)
    written = []

    sc.update(key)
    for view, fname in (("plan", "render_plan.png"), ("3d", "render_3d.png")):
        p = _plotter(pv, window_size, view, sc)
        p.add_text(sc.caption(key), position="upper_left", font_size=9, color="black", name="caption")
        p.screenshot(str(out / fname))
        p.close()
        written.append(out / fname)

    frames = np.arange(first, last + 1)
    if frames.size > max_frames:
        frames = np.unique(np.round(np.linspace(first, last, max_frames)).astype(int))
    gif = out / "render_pounding.gif"
    sc.update(int(frames[0]))
    p = _plotter(pv, gif_size, "3d", sc)
    p.open_gif(str(gif), fps=fps)
    for k in frames:
        sc.update(int(k))
        p.add_text(sc.caption(int(k)), position="upper_left", font_size=9, color="black", name="caption")
        p.write_frame()
    p.close()
    written.append(gif)
    return written
