"""Step mudforce.jax on torch tensors without host copies (DLPack), and what a call costs.

For torch-based simulators (Isaac Lab and the like): the feet's depths live
in a torch tensor on the GPU; :func:`jax.numpy.from_dlpack` wraps it as a
JAX array on the same device without copying, the jitted step runs, and
:func:`torch.from_dlpack` wraps the forces back, again without a copy. The
mud's state stays a JAX pytree between calls (donated, so updated in place).

Run::

    python examples/torch_dlpack.py               # CUDA if torch and JAX both see a GPU, else CPU
    python examples/torch_dlpack.py --n 1048576

Prints the time per call of the whole round trip (torch -> JAX -> step ->
torch) and of the jitted step alone on JAX arrays. Needs torch and
``pip install 'mudforce[jax]'`` (with a CUDA build of jaxlib for the GPU).
"""

from __future__ import annotations

import os

# keep JAX from taking most of the GPU's memory, which torch needs too; set before jax is imported
os.environ.setdefault("XLA_PYTHON_CLIENT_PREALLOCATE", "false")

import argparse
import time

import numpy as np

from mudforce import MudParameters
from mudforce.errors import MAX_FEET

#: Most timed calls ``--calls`` takes
MAX_CALLS = 10_000
#: Most depths the timed calls' inputs hold, ``(calls + 8) * n`` (each call's depths are made up front): 2**28,
#: 1 GiB of float32, above the default's 3.4 million and ``--n 1048576``'s 218 million
MAX_DEPTHS = 2**28


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    """The options, each refused in one line (exit status 2) before torch and JAX are imported: ``--calls 0``
    divided by zero after the warm-up (and ``--n 0`` or a count past memory failed inside torch or JAX)."""
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=16_384, help=f"number of feet, 1 to {MAX_FEET} (default 16384)")
    ap.add_argument("--calls", type=int, default=200, help=f"timed calls, 1 to {MAX_CALLS} (default 200)")
    args = ap.parse_args(argv)
    if not 1 <= args.n <= MAX_FEET:
        ap.error(f"--n must be from 1 to {MAX_FEET}, got {args.n}")
    if not 1 <= args.calls <= MAX_CALLS:
        ap.error(f"--calls must be from 1 to {MAX_CALLS}, got {args.calls}")
    if (args.calls + 8) * args.n > MAX_DEPTHS:
        ap.error(f"--n {args.n} with --calls {args.calls} would hold {(args.calls + 8) * args.n:,} depths, more than "
                 f"{MAX_DEPTHS:,}; lower --n or --calls")
    return args


def main(argv: list[str] | None = None) -> dict[str, float]:
    args = parse_args(argv)
    import jax
    import jax.numpy as jnp
    import torch

    import mudforce.jax as mj

    gpu = torch.cuda.is_available() and jax.default_backend() == "gpu"
    device = "cuda" if gpu else "cpu"
    dtype = torch.float32  # JAX's default float; enable jax_enable_x64 for float64
    n = args.n

    params = mj.make_params(MudParameters.from_water_content(0.25))
    step = jax.jit(mj.step, donate_argnums=0)
    state = mj.init(n)
    dt = 1e-3

    def mud_forces(state: mj.State, depths: torch.Tensor) -> tuple[mj.State, torch.Tensor]:
        """One step on torch depths [m] -> (state, torch forces [N]); no host copy either way."""
        z = jnp.from_dlpack(depths)  # a view of the torch tensor's memory
        state, f = step(state, params, z, dt)
        return state, torch.from_dlpack(f)  # a view of the JAX array's memory

    t = torch.arange(args.calls + 8, device=device, dtype=dtype)[:, None] * dt
    phase = torch.linspace(0.0, 6.28, n, device=device, dtype=dtype)
    depths = [(0.02 * torch.sin(2 * torch.pi * 1.5 * t[k] + phase) - 0.005).contiguous() for k in range(t.shape[0])]
    for k in range(8):  # compile and warm up
        state, forces = mud_forces(state, depths[k])
    # no host copy: both wraps are views of the same device memory
    z0 = jnp.from_dlpack(depths[0])
    f0 = step(mj.init(n), params, z0, dt)[1]
    zero_copy = (z0.unsafe_buffer_pointer() == depths[0].data_ptr()
                 and torch.from_dlpack(f0).data_ptr() == f0.unsafe_buffer_pointer())
    if gpu:
        torch.cuda.synchronize()
    t0 = time.perf_counter()
    for k in range(args.calls):
        state, forces = mud_forces(state, depths[8 + k])
    forces.sum().item()  # wait for the last step
    per_call = (time.perf_counter() - t0) / args.calls
    # the step alone, on JAX arrays already
    zj = [jnp.from_dlpack(d) for d in depths[8:16]]
    t0 = time.perf_counter()
    for k in range(args.calls):
        state, f = step(state, params, zj[k % 8], dt)
    f.block_until_ready()
    alone = (time.perf_counter() - t0) / args.calls
    print(f"{n} feet on {device} ({jax.default_backend()} JAX): torch -> JAX -> step -> torch {per_call * 1e6:.1f} us "
          f"per call; the jitted step alone {alone * 1e6:.1f} us per call; forces finite: "
          f"{bool(torch.isfinite(forces).all())}; no host copy (same memory both ways): {zero_copy}")
    return {"per_call_s": per_call, "step_s": alone, "max_force_N": float(np.max(np.asarray(f))),
            "zero_copy": float(zero_copy)}


if __name__ == "__main__":
    main()
