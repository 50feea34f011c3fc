"""Time to build running-bond walls and find their interfaces, 100 to 10,000 blocks.

Prints wall time per stage and per block; the ratio of per-block times shows the scaling
(sort and sweep + per-pair clipping should stay near linear). A tiny wall is run first so that
loading the compiled clipping kernels is not counted.

Measured (2 shared cores): 10,051 blocks, 29,850 interfaces found in 2.5 s (8.1 s before the
clipping moved to a numba kernel); building the blocks takes 5.7 s.
"""

import time

from dem.geometry.interfaces import find_interfaces
from dem.scenes.running_bond_wall import running_bond_wall


def main() -> None:
    print(f"{'blocks':>7} {'build_s':>8} {'interfaces':>10} {'find_s':>8} {'us/block':>9}")
    find_interfaces(running_bond_wall(2, 2, 81, 210, 70, 20.0).assembly.blocks)  # warm-up
    base = None
    for n_per_course, n_courses in ((10, 10), (25, 40), (50, 100), (100, 100)):
        start = time.perf_counter()
        scene = running_bond_wall(n_per_course, n_courses, 81, 210, 70, 20.0)
        built = time.perf_counter() - start
        start = time.perf_counter()
        iface = find_interfaces(scene.assembly.blocks)
        found = time.perf_counter() - start
        per_block = found / scene.n_blocks * 1e6
        base = base or per_block
        print(
            f"{scene.n_blocks:7d} {built:8.2f} {iface.n_interfaces:10d} {found:8.2f} "
            f"{per_block:9.1f}  (x{per_block / base:.2f} of the smallest)"
        )


if __name__ == "__main__":
    main()
