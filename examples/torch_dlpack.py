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

import jax
import jax.numpy as jnp
import numpy as np
import torch

import mudforce.jax as mj
from mudforce import MudParameters


def main(argv: list[str] | None = None) -> dict[str, float]:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=16_384, help="number of feet (default 16384)")
    ap.add_argument("--calls", type=int, default=200, help="timed calls (default 200)")
    args = ap.parse_args(argv)
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
