"""The angle of incidence as a variable: the required gap against the direction of shaking.

For each angle theta the scene's ground motion (one record, or the pair with
its first component) is turned to act along theta, the two buildings are run
without contact, and :func:`pounding.framework.studies.gap.gap_from_result` gives the
smallest clear distance at rest at which no slabs touch. A pair at theta and at
theta + 180 shakes with both components reversed, which for a linear run
without contact gives the same displacements reversed; the required gap need
not be the same (a corner that opens one way closes the other), so a full
study is 0..360 degrees, and 0..180 is the usual engineering range.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pounding.framework.model.scene import Scene

__all__ = ["AngleStudy", "gap_against_angle", "plot_gap_against_angle"]


@dataclass
class AngleStudy:
    """Required gap at each incidence angle.

    Attributes
    ----------
    angles : ndarray (na,)
        Direction of the (first) ground-motion component [deg from x].
    gaps : ndarray (na,)
        Minimum clear distance at rest for no contact [m].
    reports : list of GapReport
        The full gap report at each angle.
    """

    angles: np.ndarray
    gaps: np.ndarray
    reports: list

    @property
    def governing(self) -> int:
        """Index of the angle that needs the largest gap (the first one on a tie)."""
        return int(np.argmax(self.gaps))

    @property
    def governing_angle(self) -> float:
        return float(self.angles[self.governing])

    def to_dict(self) -> dict:
        g = self.governing
        return {
            "angles_deg": [float(a) for a in self.angles],
            "min_gap_m": [float(x) for x in self.gaps],
            "governing_angle_deg": float(self.angles[g]),
            "governing_min_gap_m": float(self.gaps[g]),
            "governing": self.reports[g].to_dict(),
        }


def gap_against_angle(scene: Scene, angles, direction=None, *, progress=None) -> AngleStudy:
    """The minimum gap for every incidence angle (module docstring).

    Parameters
    ----------
    scene : Scene
        Two buildings; its ground motion (GroundMotion or GroundMotionPair).
    angles : array_like (na,)
        [deg], the direction given to the (first) component.
    direction : see :func:`pounding.framework.studies.gap.minimum_gap`
        Direction along which the gap is measured (fixed for all angles).
    progress : callable(done, total), optional
    """
    from pounding.framework.studies.gap import minimum_gap

    angles = np.asarray(angles, dtype=float).reshape(-1)
    reports = []
    for i, a in enumerate(angles):
        turned = scene.with_ground_motion(scene.ground_motion.with_angle(float(a)))
        reports.append(minimum_gap(turned, direction))
        if progress is not None:
            progress(i + 1, angles.size)
    return AngleStudy(angles, np.array([r.min_gap for r in reports]), reports)


def plot_gap_against_angle(study: AngleStudy, path, title: str = "") -> Path:
    """PNG of the required gap against the incidence angle, the governing angle marked."""
    from matplotlib.figure import Figure

    path = Path(path)
    fig = Figure(figsize=(7, 4.2), dpi=120, layout="constrained")
    ax = fig.add_subplot()
    ax.plot(study.angles, study.gaps, marker="o", ms=3)
    g = study.governing
    ax.plot([study.angles[g]], [study.gaps[g]], "r*", ms=12,
            label=f"governing: {study.angles[g]:g} deg, {study.gaps[g]:.4f} m")
    ax.set_xlabel("incidence angle of the (first) component from x [deg]")
    ax.set_ylabel("minimum gap for no pounding [m]")
    ax.set_title(title or "Required separation gap against the angle of incidence")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.savefig(path, format="png")
    return path
