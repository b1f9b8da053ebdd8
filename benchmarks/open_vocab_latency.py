"""Latency of each stage of the open-vocabulary perception pipeline on a simulated scene.

The models are loaded from local directories (``--detector``: an ``Owlv2ForObjectDetection``
with its tokenizer; ``--segmenter``: a ``SamModel``), or with ``--tiny`` built with random
weights (which find random things: the figures are then the pipeline's overhead, not the real
models'). On one seeded tabletop scene (4 cameras), each stage runs ``--repeats`` times after one
warm-up; the median is reported: the detector and the segmenter per camera image (the segmenter
with the detector's boxes as prompts), the tracker step and the fusion (masks → 3-D instances →
labelled cloud) per observation of all cameras. The last line is machine-readable.

    MUJOCO_GL=egl python benchmarks/open_vocab_latency.py --tiny
    MUJOCO_GL=egl python benchmarks/open_vocab_latency.py --detector DIR --segmenter DIR
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

os.environ.setdefault("MUJOCO_GL", "egl")
os.environ.setdefault("HF_HUB_OFFLINE", "1")

import numpy as np
from rich.console import Console
from rich.table import Table

from voxposer.envs import SceneLayout, TabletopWorld
from voxposer.perception.open_vocab import (
    MaskTracker,
    OwlDetector,
    SamSegmenter,
    ViewMask,
    fuse_masks,
    labelled_cloud,
)
from voxposer.perception.open_vocab.fusion import world_points
from voxposer.perception.open_vocab.tiny_models import save_tiny_models


def median_ms(fn: Callable[[], Any], repeats: int) -> tuple[float, Any]:
    """The median wall time [ms] of ``repeats`` calls of ``fn`` after one warm-up, and its last
    result."""
    result = fn()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        times.append((time.perf_counter() - start) * 1e3)
    return float(np.median(times)), result


def run(detector: OwlDetector, segmenter: SamSegmenter, queries: list[str], repeats: int,
        seed: int) -> dict[str, Any]:
    """Time every stage on one seeded scene; the figures of the machine-readable line."""
    world = TabletopWorld()
    try:
        world.reset(np.random.default_rng(seed), SceneLayout())
        obs = world.observe(rgb=True)
        grid = world.grid
    finally:
        world.close()
    frames = obs.cameras
    det_ms, seg_ms, masks = [], [], []
    for cam, frame in enumerate(frames):
        ms, found = median_ms(lambda f=frame: detector.detect(f.rgb, queries), repeats)
        det_ms.append(ms)
        boxes = np.array([d.box for d in found]).reshape(-1, 4)
        ms, segments = median_ms(lambda f=frame, b=boxes: segmenter.segment(f.rgb, b), repeats)
        seg_ms.append(ms)
        masks += [ViewMask(cam, d.query, m, d.score) for d, m in zip(found, segments, strict=True)]

    def fuse() -> Any:
        instances = fuse_masks(frames, masks, grid, queries, points=world_points(frames))
        labelled_cloud(frames, instances, grid)
        return instances

    fusion_ms, instances = median_ms(fuse, repeats)
    tracker = MaskTracker(segmenter)
    tracker_ms, step = median_ms(lambda: tracker.step(frames, instances, grid), repeats)
    h, w = frames[0].rgb.shape[:2]
    return {"detector_ms": round(float(np.median(det_ms)), 1),
            "segmenter_ms": round(float(np.median(seg_ms)), 1),
            "tracker_ms": round(tracker_ms, 1), "fusion_ms": round(fusion_ms, 1),
            "boxes": len(masks), "instances": len(instances), "tracked": len(step.instances),
            "cameras": len(frames), "image": f"{w}x{h}", "repeats": repeats}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--detector", type=Path, help="directory of an OWLv2 model")
    parser.add_argument("--segmenter", type=Path, help="directory of a SAM model")
    parser.add_argument("--tiny", action="store_true", help="build tiny random models instead")
    parser.add_argument("--queries", default="block,drawer handle,table",
                        help="comma-separated text queries")
    parser.add_argument("--threshold", type=float, default=None,
                        help="detector score threshold (default 0.1; 0.0 with --tiny)")
    parser.add_argument("--repeats", type=int, default=5, help="timed runs per stage")
    parser.add_argument("--seed", type=int, default=0, help="scene seed")
    parser.add_argument("--threads", type=int, default=None,
                        help="torch intra-op threads (default: torch's; 1 on a busy machine)")
    args = parser.parse_args()
    if not args.tiny and (args.detector is None or args.segmenter is None):
        parser.error("give --detector DIR and --segmenter DIR, or --tiny")
    console = Console(stderr=True, width=120)
    if args.threads is not None:
        import torch

        torch.set_num_threads(args.threads)
    threshold = args.threshold if args.threshold is not None else (0.0 if args.tiny else 0.1)
    with tempfile.TemporaryDirectory() as tmp:
        det_dir, seg_dir = (save_tiny_models(tmp) if args.tiny
                            else (args.detector, args.segmenter))
        detector = OwlDetector.from_pretrained(det_dir, threshold=threshold)
        segmenter = SamSegmenter.from_pretrained(seg_dir)
    line = run(detector, segmenter, [q.strip() for q in args.queries.split(",")],
               args.repeats, args.seed)
    import torch

    line["threads"] = torch.get_num_threads()
    models = "tiny random models" if args.tiny else f"{det_dir} + {seg_dir}"
    table = Table(title=f"open-vocabulary perception latency ({models})")
    for col in ("stage", "median (ms)", "per"):
        table.add_column(col, justify="right")
    for stage, per in (("detector", "image"), ("segmenter", "image"), ("tracker", "observation"),
                       ("fusion", "observation")):
        table.add_row(stage, f"{line[f'{stage}_ms']:.1f}", per)
    console.print(table)
    print(" ".join(f"{k}={v}" for k, v in line.items()))


if __name__ == "__main__":
    main()
