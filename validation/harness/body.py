"""Extractors of flow around a body of revolution on narwhal's six-block grid
(solver/mesh/body_of_revolution.hpp): the axis x, the nose at x = 0, the rear pole
where the block 'tail' closes on the axis."""
import numpy as np

from .errors import HarnessError
from .schema import extractor


def axis_velocity(zone):
    """u along the axis behind the body: the mean of the four cells around the 'tail'
    block's centre grid line (the axis, node (n/2, n/2) of its square), per layer
    from the wall out. Returns (x of the rear pole, x of the layers, u)."""
    nk, nj, ni = zone.fields["u"].shape
    if ni != nj or ni % 2:
        raise HarnessError("axis extraction needs the tail block's square with an even cell count per side")
    m = ni // 2
    u = zone.fields["u"][:, m - 1:m + 1, m - 1:m + 1].mean(axis=(1, 2))
    x = zone.centres[:, m - 1:m + 1, m - 1:m + 1, 0].mean(axis=(1, 2))
    axis_nodes = zone.x[:, m, m, :]
    if np.max(np.abs(axis_nodes[:, 1:])) > 1e-9 * max(1.0, float(np.max(np.abs(axis_nodes[:, 0])))):
        raise HarnessError("axis extraction: the tail block's centre line is not the x axis")
    return float(axis_nodes[0, 0]), x, u


@extractor("recirculation_length", "diameter")
def recirculation_length(ctx, spec, run_id):
    """Length of the recirculation bubble behind the body, from the rear pole to where
    u on the axis turns positive, in diameters (0 without a bubble)."""
    tails = [z for z in ctx.solution(run_id) if z.name == "tail"]
    if len(tails) != 1:
        raise HarnessError(f"recirculation_length: run '{run_id}' has no single block 'tail' (a body-of-revolution grid)")
    rear, x, u = axis_velocity(tails[0])
    diameter = float(spec.get("diameter", 1.0))
    length = 0.0
    if u[0] < 0.0:
        turn = np.nonzero(u >= 0.0)[0]
        if turn.size == 0:
            raise HarnessError(f"recirculation_length: u < 0 along the whole axis of '{run_id}'")
        k = int(turn[0])
        w = -u[k - 1] / (u[k] - u[k - 1])
        length = ((1 - w) * x[k - 1] + w * x[k] - rear) / diameter
    return length
