"""Tracing many bundles of rays in batches, on several threads, with the same result for any split.

A batch is as many consecutive bundles (receptors or pixels) as fit in a
number of rays; each thread traces one batch at a time. numpy and Embree
release the GIL, so one thread shades its batch while another's rays are
cast. A bundle's random numbers depend on nothing but its index, so the
results depend neither on the batch size nor on the number of threads.
"""

from concurrent.futures import ThreadPoolExecutor
from typing import NamedTuple


class TraceSettings(NamedTuple):
    """How bundles are traced: rays per bundle, path depth, seed, rays per batch, threads."""

    samples: int
    depth: int
    seed: int
    batch_rays: int
    threads: int = 1

    @classmethod
    def from_config(cls, trace, threads=1, samples=None):
        """The settings of a config's ``trace`` section; ``samples`` overrides its samples per receptor."""
        return cls(samples=trace["samples_per_receptor"] if samples is None else samples, depth=trace["depth"],
                   seed=trace["seed"], batch_rays=trace["batch_rays"], threads=threads)


def in_batches(trace, first, last, settings):
    """Run ``trace(lo, hi)`` over bundles ``first``..``last`` in batches, on ``settings.threads`` threads.

    Yields ``(lo, hi), trace(lo, hi)`` in order.
    """
    step = max(1, settings.batch_rays // settings.samples)
    bounds = [(lo, min(last, lo + step)) for lo in range(first, last, step)]
    pool = ThreadPoolExecutor(max(1, settings.threads))
    try:
        yield from zip(bounds, pool.map(lambda b: trace(*b), bounds))
    finally:
        # Interrupted: finish only the batches already running.
        pool.shutdown(cancel_futures=True)
