"""Tracing many bundles of rays in batches, on several threads, with the same result for any split.

A bundle is a receptor's cone or a pixel, traced with a number of samples.
A batch holds as many consecutive bundles as fit in ``batch_rays`` rays; a
bundle of more than :data:`SAMPLE_BLOCK` samples is traced in blocks of that
many, each a bundle of its own, so that no batch outgrows ``batch_rays``
however many samples a bundle has. Each thread traces one batch at a time
(numpy and Embree release the GIL, so one thread shades its batch while
another's rays are cast), and only a few batches are queued ahead, so that
memory stays bounded and Ctrl-C stops a run within a batch's time.

A block's random numbers depend on nothing but its bundle's index and its
samples' indices, and a bundle's blocks are summed in their order, so the
results depend neither on the batch size nor on the number of threads.
"""

from collections import deque
from concurrent.futures import ThreadPoolExecutor
from typing import NamedTuple

import numpy as np

from beeoptics.io.validation import config_default

#: Samples in a block: a bundle with more is traced in blocks of this many. The
#: smallest ``batch_rays`` the config allows, so that a block always fits a batch.
SAMPLE_BLOCK = 1024
#: Batches queued per thread beyond those running.
QUEUED_PER_THREAD = 2


class TraceSettings(NamedTuple):
    """How bundles are traced: rays per bundle, path depth, seed, rays per batch, threads, and how the sky
    is sampled (:func:`beeoptics.light.integrator.trace_paths`)."""

    samples: int
    depth: int
    seed: int
    batch_rays: int
    threads: int = 1
    sky_sampling: str = config_default("trace.sky_sampling")

    @classmethod
    def from_config(cls, trace, threads=1, samples=None):
        """The settings of a config's ``trace`` section; ``samples`` overrides its samples per receptor."""
        return cls(samples=trace["samples_per_receptor"] if samples is None else samples, depth=trace["depth"],
                   seed=trace["seed"], batch_rays=trace["batch_rays"], threads=threads,
                   sky_sampling=trace.get("sky_sampling", cls._field_defaults["sky_sampling"]))


class Blocks(NamedTuple):
    """Units of tracing: for each, its bundle, the index of its first sample, and its samples."""

    bundle: np.ndarray
    first_sample: np.ndarray
    samples: int


def _batches(first, last, settings):
    """The blocks of bundles ``first``..``last``, batched: lists of :class:`Blocks`, in order.

    Made one batch at a time, so that a run of 10⁸ samples a receptor does
    not hold the list of its blocks.
    """
    per_bundle = -(-settings.samples // SAMPLE_BLOCK)
    size = min(settings.samples, SAMPLE_BLOCK)
    step = max(1, settings.batch_rays // size)
    for lo in range(0, (last - first) * per_bundle, step):
        unit = np.arange(lo, min((last - first) * per_bundle, lo + step))
        bundle, start = first + unit // per_bundle, unit % per_bundle * size
        count = np.minimum(size, settings.samples - start)
        # A batch holds blocks of one size: the last block of a bundle may be shorter.
        yield [Blocks(bundle[count == c], start[count == c], int(c)) for c in np.unique(count)]


def trace_bundles(trace, first, last, settings, columns, progress=None):
    """Each bundle's mean, traced in batches of blocks on ``settings.threads`` threads.

    Parameters
    ----------
    trace : callable
        ``trace(blocks)`` of :class:`Blocks` returns each block's weighted
        mean (k, m) and its sum of weights (k,).
    first, last : int
        The bundles to trace.
    settings : TraceSettings
    columns : int
        m, the length of a bundle's result.
    progress : callable, optional
        Called with (bundles done, bundles in all) after each batch.

    Returns
    -------
    ndarray, shape (last − first, m)
        Each bundle's weighted mean over all its samples.
    """
    n = last - first
    means, weights = np.zeros((n, columns)), np.zeros(n)
    done = 0
    with ThreadPoolExecutor(max(1, settings.threads)) as pool:
        batches = iter(_batches(first, last, settings))
        queue = deque()
        try:
            while True:
                while len(queue) < settings.threads * (1 + QUEUED_PER_THREAD):
                    batch = next(batches, None)
                    if batch is None:
                        break
                    queue.append(pool.submit(lambda b: [(blocks, *trace(blocks)) for blocks in b], batch))
                if not queue:
                    break
                results = queue.popleft().result()
                rows = np.concatenate([blocks.bundle for blocks, _, _ in results]) - first
                mean = np.concatenate([m for _, m, _ in results])
                if settings.samples <= SAMPLE_BLOCK:
                    means[rows] = mean
                else:
                    # Each bundle's blocks are summed in the order of their samples, whichever
                    # batches they came in: batches arrive in order, and within one np.add.at
                    # adds repeated rows in the order given.
                    start = np.concatenate([blocks.first_sample for blocks, _, _ in results])
                    weight = np.concatenate([w for _, _, w in results])
                    order = np.lexsort((start, rows))
                    np.add.at(means, rows[order], (mean * weight[:, None])[order])
                    np.add.at(weights, rows[order], weight[order])
                done = max(done, int(rows.max()) + 1)
                if progress is not None:
                    progress(done, n)
        finally:
            # Interrupted: finish only the batches already running.
            for future in queue:
                future.cancel()
    if settings.samples > SAMPLE_BLOCK:
        means /= weights[:, None]
    return means
