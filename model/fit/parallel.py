# SPDX-License-Identifier: Apache-2.0
"""The search's descents on Dask, the trade study's engine (``trade.make_client``).

Owns ``search_candidates_dask``: the shading mode and the families that meet the target in it
are chosen here (a few images); then each start's descent policy (``search.POLICIES``) runs as
one task on the cluster — a LocalCluster of
``workers`` processes or the scheduler at ``scheduler`` — which rasterises the scene, renders
its own reference and descends; the figures every task found come back into the caller's
evaluator (and so into its cache file).  The designs equal the ones ``search_candidates`` finds
in one process: each descent is deterministic.  May import ``model.fit.search``, ``model.render``
and ``model.study.trade``.
"""

from __future__ import annotations

from model.fit import search
from model.fit.analyse import SceneNeeds
from model.render import raster, scene
from model.study.trade import make_client


def descend_task(
    the_scene: scene.Scene,
    key: str,
    start: search.SearchResult,
    target: search.Target,
    policy: str,
    known: dict[str, dict],
) -> tuple[search.SearchResult, int, dict[str, dict]]:
    """One descent on a worker, knowing the figures ``known`` already: (its result, images it
    rendered, every figure it holds)."""
    evaluate = search.Evaluator(raster.rasterise(the_scene), key)
    evaluate.absorb(known)
    result = search.descend(evaluate, start, target, policy)
    return result, evaluate.renders, evaluate.known()


def search_candidates_dask(
    the_scene: scene.Scene,
    evaluate: search.Evaluator,
    needs: SceneNeeds,
    target: search.Target,
    lanes: int = 2,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    families: tuple[str, ...] = search.FAMILIES,
) -> tuple[list[search.SearchResult], int]:
    """``search.search_candidates`` with the descents on Dask: (candidates, images rendered on
    the workers)."""
    starts = search.choose_starts(evaluate, needs, target, lanes, families=families)
    if not starts[0].met:
        evaluate.save()
        return starts, 0
    client = make_client(workers, scheduler)
    try:
        known = client.scatter(evaluate.known(), broadcast=True)
        futures = [
            client.submit(
                descend_task,
                the_scene,
                evaluate.scene_key,
                start,
                target,
                policy,
                known,
                pure=False,
            )
            for start in starts
            for policy in search.POLICIES
        ]
        done = client.gather(futures)
    finally:
        client.close()
    found: list[search.SearchResult] = []
    rendered = 0
    for result, renders, figures in done:
        evaluate.absorb(figures)
        rendered += renders
        if all(r.config != result.config for r in found):
            found.append(result)
    evaluate.save()
    return found, rendered
