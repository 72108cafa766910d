"""validate of one link over a long sweep: one task, against blocks of its positions on a cluster.

The six_bar case's coupler, its sweep made ``--positions`` input angles over a turn (all distinct
poses), each compared on the default three-level refinement study. Timed: the link as one task in
this process; on a LocalCluster of 2 workers (``linkstress.executors.local_cluster``, warmed up)
with the blocks ``validate`` chooses for 2 workers, and with blocks of ``--block`` positions. Each
block meshes and factorises the link anew: the sum of the tasks' times is the work done, the wall
time what a user waits. Every run's JSON must equal the one-task run's but for timings.

    python -m linkstress.validation.bench.blocks [--positions 360] [--block 64]
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
import time
from pathlib import Path

CASE = Path(__file__).resolve().parents[1] / "cases" / "six_bar"
LINK = "coupler"


def long_sweep(folder: Path, positions: int) -> Path:
    """The six_bar case in ``folder`` with ``positions`` input angles over a turn, validating the coupler only."""
    shutil.copytree(CASE, folder, dirs_exist_ok=True)
    scene = folder / "scene.toml"
    text = scene.read_text().replace(
        "input_angle_deg = {start = 0.0, stop = 350.0, num = 36}",
        f"input_angle_deg = {{start = 0.0, stop = {360 - 360 / positions!r}, num = {positions}}}",
    )
    scene.write_text(text + f'\n[analysis]\nvalidate = ["{LINK}"]\n')
    return scene


def timed(scene: Path, positions: int, where, block: int | None = None) -> tuple[float, float, dict]:
    """Wall time [s], the link's task time summed [s], and the JSON less its timings."""
    from linkstress.analysis import plan_for
    from linkstress.scene import load_scene
    from linkstress.validation.report import validation_json
    from linkstress.validation.validate_scene import validate_scene

    loaded = load_scene(scene)
    start = time.perf_counter()
    result = validate_scene(loaded, plan_for(loaded), positions, executor=where, block=block)
    wall = time.perf_counter() - start
    return wall, result.seconds[LINK], _without_timing(validation_json(result))


def _without_timing(data):
    if isinstance(data, dict):
        return {k: _without_timing(v) for k, v in data.items() if "seconds" not in k}
    if isinstance(data, list):
        return [_without_timing(v) for v in data]
    return data


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--positions", type=int, default=360)
    parser.add_argument("--block", type=int, default=64)
    args = parser.parse_args()
    from distributed import Client

    from linkstress.executors import DaskExecutor, LocalExecutor, local_cluster
    from linkstress.validation.validate_scene import position_blocks

    with tempfile.TemporaryDirectory() as tmp:
        scene = long_sweep(Path(tmp) / "six_bar", args.positions)
        rows = [("this process, one task", *timed(scene, args.positions, LocalExecutor()), 1)]
        with local_cluster(2) as cluster, Client(cluster) as client:
            client.run(lambda: __import__("linkstress.validation.validate_scene"))
            where = DaskExecutor(client, "local")
            auto = len(position_blocks(args.positions, 1, where.workers))
            rows.append(("2 workers, blocks validate chooses", *timed(scene, args.positions, where), auto))
            given = len(position_blocks(args.positions, 1, where.workers, args.block))
            rows.append((f"2 workers, --positions-per-task {args.block}", *timed(scene, args.positions, where, args.block), given))
    reference = rows[0][3]
    print(f"six_bar {LINK}, {args.positions} positions, three-level refinement study")
    print()
    print("| run | tasks | wall time [s] | tasks' time summed [s] | speed-up | same JSON |")
    print("|---|---:|---:|---:|---:|---|")
    for name, wall, work, data, tasks in rows:
        print(f"| {name} | {tasks} | {wall:.1f} | {work:.1f} | {rows[0][1] / wall:.2f} | {'yes' if data == reference else 'NO'} |")
    return 0 if all(row[3] == reference for row in rows) else 1


if __name__ == "__main__":
    raise SystemExit(main())
