"""Tracing many bundles of rays in batches, on several threads, with the same result for any split.

A bundle is a receptor's cone or a pixel, traced with a number of samples,
as :data:`~beeoptics.light.precision.REPLICATES` independent replicates of a share of them each (a
pixel as one), so that each bundle's mean comes with an honest standard
error (:func:`~beeoptics.light.precision.replicate_samples`). A batch holds as many consecutive
replicates' samples as fit in about ``batch_rays`` rays; a replicate of
more than :data:`SAMPLE_BLOCK` samples is traced in blocks of that many,
each a unit of its own, so that no batch outgrows ``batch_rays`` however
many samples a bundle has. Each thread traces one batch at a time (numpy
and Embree release the GIL, so one thread shades its batch while another's
rays are cast), and only a few batches are queued ahead, so that memory
stays bounded and Ctrl-C stops a run within a batch's time.

A block's random numbers depend on nothing but its bundle's index, its
replicate and its samples' indices, and a replicate's blocks are summed in
their order, so the results depend neither on the batch size nor on the
number of threads.
"""

import logging
from collections import deque
from concurrent.futures import ThreadPoolExecutor
from typing import NamedTuple

import numpy as np

from beeoptics.io.errors import InputError
from beeoptics.io.validation import config_default
from beeoptics.light.precision import Precision, class_forms
from beeoptics.light.sampler import REPLICATE_SHIFT

log = logging.getLogger("beeoptics")

#: Samples in a block: a bundle with more is traced in blocks of this many. The
#: smallest ``batch_rays`` the config allows, so that a block always fits a batch.
SAMPLE_BLOCK = 1024
#: Units of tracing listed at once (a few MB of indices).
UNITS_LISTED = 1 << 16
#: Batches queued per thread beyond those running.
QUEUED_PER_THREAD = 2


class TraceSettings(NamedTuple):
    """How bundles are traced: rays per bundle, path depth, seed, rays per batch, threads, how the sky
    is sampled (:func:`beeoptics.light.integrator.trace_paths`), and the precision asked of receptor cones
    (:class:`~beeoptics.light.precision.Precision`; None: ``samples`` each)."""

    samples: int
    depth: int
    seed: int
    batch_rays: int
    threads: int = 1
    sky_sampling: str = config_default("trace.sky_sampling")
    precision: Precision | None = None

    @classmethod
    def from_config(cls, trace, threads=1, samples=None, classes=None, noise=None):
        """The settings of a config's ``trace`` section; ``samples`` overrides its samples per receptor.

        ``classes``, the number of receptor classes whose catches the
        section's ``precision`` is asked of (without it, views through
        pixels: fixed samples); ``noise``, the forms a ``target`` of
        ``auto`` asks of them, from their receptor set's noise
        (:func:`beeoptics.vision.uncertainty.noise_forms`; None where the set
        gives none: fixed samples, and a warning).
        """
        asked = {**config_default("trace.precision"), **trace.get("precision", {})}
        if asked["min_samples"] > asked["max_samples"]:
            raise InputError("config", "trace.precision.min_samples",
                             f"{asked['min_samples']} is more than max_samples, {asked['max_samples']}")
        target, forms = asked["target"], None
        if classes is not None and target is not None:
            forms = noise if target == "auto" else class_forms(target, classes)
            if forms is None:
                log.warning("trace.precision.target auto: no receptor noise (the receptor set's Weber "
                            "fractions) to derive a precision from; tracing the fixed samples_per_receptor")
        precision = None if forms is None else Precision(forms, asked["floor"], asked["min_samples"],
                                                         asked["max_samples"])
        return cls(samples=trace["samples_per_receptor"] if samples is None else samples, depth=trace["depth"],
                   seed=trace["seed"], batch_rays=trace["batch_rays"], threads=threads,
                   sky_sampling=trace.get("sky_sampling", cls._field_defaults["sky_sampling"]), precision=precision)


class Blocks(NamedTuple):
    """Units of tracing: for each, its bundle, the index of its first sample, and its samples.

    A first sample's index holds its replicate above :data:`~beeoptics.light.sampler.REPLICATE_SHIFT`
    bits (:mod:`beeoptics.light.sampler`)."""

    bundle: np.ndarray
    first_sample: np.ndarray
    samples: int


def _batches(first, samples, replicates, batch_rays):
    """The blocks of bundles ``first``.. (``samples`` per replicate of each), batched: lists of :class:`Blocks`.

    Units run bundle by bundle, each bundle's replicates in order, each
    replicate's blocks in order; a batch is the units that start within a
    window short enough that it holds at most ``batch_rays`` rays. Listed a
    few bundles at a time, so that a run of 10⁸ samples a receptor does not
    hold the list of all its blocks. Within a listing, replicates traced in
    one block are ordered by their samples, so that a batch holds few sizes:
    each size is one call of ``trace``, which costs some milliseconds
    besides its rays (an adaptive trace of 486 sizes made 5,375 calls of
    2,000 rays each, and spent more than half its time between them). A
    block's result does not depend on the others in its call; a replicate
    of several blocks keeps its blocks' order, in which they are summed.
    """
    blocks = -(-samples // SAMPLE_BLOCK)  # per replicate of each bundle
    per_bundle = blocks * len(replicates)
    window = max(1, batch_rays - int(min(SAMPLE_BLOCK, samples.max(initial=1))) + 1)
    ends = np.cumsum(per_bundle)
    lo = 0
    while lo < len(samples):
        hi = max(lo + 1, int(np.searchsorted(ends, ends[lo] - per_bundle[lo] + UNITS_LISTED, "right")))
        unit = np.arange(ends[hi - 1] - ends[lo] + per_bundle[lo])
        bundle = lo + np.repeat(np.arange(hi - lo), per_bundle[lo:hi])
        within = unit - np.repeat(ends[lo:hi] - ends[lo] + per_bundle[lo] - per_bundle[lo:hi], per_bundle[lo:hi])
        replicate = np.asarray(replicates)[within // blocks[bundle]]
        start = within % blocks[bundle] * SAMPLE_BLOCK
        count = np.minimum(SAMPLE_BLOCK, samples[bundle] - start)
        # Replicates of several blocks first, as listed; then the others by size (a stable sort).
        order = np.argsort(np.where(blocks[bundle] > 1, 0, count), kind="stable")
        bundle, replicate, start, count = bundle[order], replicate[order], start[order], count[order]
        batch = (np.cumsum(count) - count) // window
        edges = np.flatnonzero(np.diff(batch, prepend=-1, append=batch[-1] + 1))
        for a, b in zip(edges[:-1], edges[1:]):
            ids, first_sample, c = first + bundle[a:b], (replicate[a:b] << REPLICATE_SHIFT) + start[a:b], count[a:b]
            # A batch holds blocks of one size: the last block of a replicate may be shorter.
            yield [Blocks(ids[c == k], first_sample[c == k], int(k)) for k in np.unique(c)]
        lo = hi


def trace_bundles(trace, first, last, settings, columns, samples, replicates, progress=None):
    """Each bundle's mean of each replicate, traced in batches of blocks on ``settings.threads`` threads.

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
    samples : ndarray of int, shape (last − first,)
        Each bundle's samples per replicate.
    replicates : sequence of int
        The replicates' indices (0 … K − 1, K of :func:`replicate_samples`, for one estimate).
    progress : callable, optional
        Called with (bundles done, bundles in all) after each batch, the bundles done counted in rays.

    Returns
    -------
    ndarray, shape (last − first, len(replicates), m)
        Each bundle's weighted mean over each replicate's samples.
    """
    n = last - first
    samples = np.asarray(samples, np.int64)
    r = len(replicates)
    position = np.zeros(max(replicates, default=0) + 1, np.int64)
    position[list(replicates)] = np.arange(r)
    whole = samples <= SAMPLE_BLOCK
    means, weights = np.zeros((n * r, columns)), np.zeros(n * r)
    done, total = 0, max(1, int(samples.sum()) * r)
    # A trace of fewer rays than the threads' batches hold is shared among them all (a closed loop's look of
    # a few samples a receptor would otherwise be one batch, shaded on one thread): the split moves no result.
    batch_rays = min(settings.batch_rays, max(SAMPLE_BLOCK, -(-int(samples.sum()) * r // max(1, settings.threads))))
    with ThreadPoolExecutor(max(1, settings.threads)) as pool:
        batches = _batches(first, samples, replicates, batch_rays)
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
                bundle = np.concatenate([blocks.bundle for blocks, _, _ in results]) - first
                start = np.concatenate([blocks.first_sample for blocks, _, _ in results])
                rows = bundle * r + position[start >> REPLICATE_SHIFT]
                mean = np.concatenate([m for _, m, _ in results])
                one = whole[bundle]
                if one.all():
                    # Every replicate in one block (few samples a bundle): each keeps its mean as traced.
                    means[rows] = mean
                else:
                    # A replicate traced in one block keeps its mean as traced, to the last bit.
                    means[rows[one]] = mean[one]
                    # A replicate's blocks are summed in the order of their samples, whichever batches
                    # they came in: batches arrive in order, and within one np.add.at adds repeated
                    # rows in the order given.
                    weight = np.concatenate([w for _, _, w in results])
                    order = np.lexsort((start, rows))
                    order = order[~one[order]]
                    np.add.at(means, rows[order], mean[order] * weight[order, None])
                    np.add.at(weights, rows[order], weight[order])
                # Counted in rays, as batches come in order of size, not of bundles.
                done += sum(len(blocks.bundle) * blocks.samples for blocks, _, _ in results)
                if progress is not None:
                    progress(n * done // total, n)
        finally:
            # Interrupted: finish only the batches already running.
            for future in queue:
                future.cancel()
    split = ~np.repeat(whole, r)
    means[split] /= weights[split, None]
    return means.reshape(n, r, columns)
