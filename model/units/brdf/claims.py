# SPDX-License-Identifier: Apache-2.0
"""BRDF family: the thesis's accuracy claims, checked against the exact worst errors.

Owns ``Claim`` and ``CLAIMS`` (each approximation's claimed maximum relative error and the n it
is claimed for), ``ClaimCheck`` with ``check_claim`` / ``check_claims`` (the exact worst error
over n = 1..1000 and over the claim's n, and the n where the claim fails) and
``format_claims_table`` (the markdown table of scripts/brdf_claims.py and docs/brdf.md).  The
cos^k(a d) rows come from ``model.units.specular.brdf_max_rel_error`` with the a that is exact
at the inflection point (``alpha = "inflection"``).  May import numpy, ``model.units.fixed``,
``model.units.specular``'s public names and ``approx``.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from decimal import ROUND_HALF_UP, Decimal

import numpy as np

from model.units import fixed
from model.units.brdf.approx import FORMS, worst_errors
from model.units.specular import N_MAX, brdf_max_rel_error

COS_K = "cos_k"
"""``Claim.form`` of the patent's structure cos^k(a d) (with ``Claim.k``)."""
INV_E = math.exp(-1.0)
"""The level cos^n = 1/e down to which the piecewise form's 4 % holds (docs/brdf.md says why
this is the zone the claim fits)."""
TIE_RTOL = 1e-9
"""n whose worst error is within this much (relative) of the largest are all named."""


@dataclass(frozen=True)
class Claim:
    """One claimed bound: ``form``'s relative error stays within ``percent`` % for n_lo..n_hi,
    over the epicentre (or, with ``level``, where cos^n d >= level)."""

    label: str
    form: str  # a name of approx.FORMS, or COS_K
    percent: str  # as the thesis writes it, "3.14": the bound and its digits
    n_lo: int = 1
    n_hi: int = N_MAX
    level: float | None = None
    k: int = 0  # the k of cos^k(a d) (form COS_K only)

    def __post_init__(self) -> None:
        legal = (*FORMS, COS_K)
        if self.form not in legal:
            raise ValueError(f"form = {self.form!r} is out of range: legal are {legal}")
        fixed.check_operand("n_lo", self.n_lo, 1, N_MAX)
        fixed.check_operand("n_hi", self.n_hi, self.n_lo, N_MAX)

    @property
    def bound(self) -> float:
        return float(Decimal(self.percent) / 100)

    @property
    def digits(self) -> int:
        """Decimals the thesis gives the bound with (in %)."""
        return max(0, -Decimal(self.percent).as_tuple().exponent)

    @property
    def n_text(self) -> str:
        return _ranges(list(range(self.n_lo, self.n_hi + 1)))


CLAIMS: tuple[Claim, ...] = (
    Claim("quadratic a cos^2 + b cos, matched at the inflection level", "quadratic", "3.14"),
    Claim("cubic, first approach (Q = 0.5)", "cubic", "0.67"),
    Claim("piecewise cubic / bloom, over the epicentre", "piecewise", "4"),
    Claim("piecewise cubic / bloom, down to cos^n = 1/e", "piecewise", "4", level=INV_E),
    Claim("2^(n log2 cos), 2^x ~ 1 - log2(1 - x)/2", "log2", "0.29"),
    Claim("cosine-quadratic (1 - (7n/16)(1 - cos))^2", "cosine_quadratic", "2", 25, N_MAX),
    Claim("cosine-quadratic (1 - (7n/16)(1 - cos))^2", "cosine_quadratic", "3", 1, 24),
    Claim("cos^2(a d), a exact at the inflection point", COS_K, "1.1", 2, N_MAX, k=2),
    Claim("cos^3(a d), a exact at the inflection point", COS_K, "0.7", 3, N_MAX, k=3),
)
"""The thesis's claims (chapter 2), in its order.  n ranges: the cosine-quadratic's are the
thesis's (25..1000, "otherwise" = 1..24); cos^k(a d) is stated for k <= n; the rest for every n.
The piecewise form's claim is checked twice: over the epicentre, where the form is the cubic,
and down to cos^n = 1/e, the zone whose n -> infinity limit is the claimed 4 %."""


@dataclass(frozen=True)
class ClaimCheck:
    """A claim against the exact worst errors (``errors[n - 1]`` for n = 1..1000)."""

    claim: Claim
    errors: np.ndarray

    def _worst(self, lo: int, hi: int) -> tuple[float, list[int]]:
        part = self.errors[lo - 1 : hi]
        top = float(part.max())
        return top, [lo + int(i) for i in np.flatnonzero(part >= top * (1 - TIE_RTOL))]

    @property
    def worst(self) -> tuple[float, list[int]]:
        """The largest error over n = 1..1000 and every n that reaches it (to ``TIE_RTOL``)."""
        return self._worst(1, N_MAX)

    def worst_from(self, lo: int) -> tuple[float, list[int]]:
        """The same over n = lo..1000."""
        return self._worst(lo, N_MAX)

    @property
    def worst_in_range(self) -> tuple[float, list[int]]:
        """The same over the claim's own n."""
        return self._worst(self.claim.n_lo, self.claim.n_hi)

    @property
    def failing(self) -> list[int]:
        """The claim's n whose exact worst error exceeds the bound."""
        c = self.claim
        return [n for n in range(c.n_lo, c.n_hi + 1) if self.errors[n - 1] > c.bound]

    @property
    def holds(self) -> bool:
        return not self.failing

    @property
    def rounded(self) -> str:
        """The worst error over the claim's n, rounded (half up) to the claim's digits, in %."""
        q = Decimal(1).scaleb(-self.claim.digits)
        if self.worst_in_range[0] >= 10.0:
            return f"{self.worst_in_range[0] * 100:.3g}"
        return str((Decimal(self.worst_in_range[0]) * 100).quantize(q, rounding=ROUND_HALF_UP))

    @property
    def holds_rounded(self) -> bool:
        return Decimal(self.rounded) <= Decimal(self.claim.percent)


def claim_errors(claim: Claim) -> np.ndarray:
    """The exact worst relative errors of the claim's form for n = 1..1000 (over its zone)."""
    if claim.form == COS_K:
        return _cos_k_errors(claim.k)
    return worst_errors(claim.form, claim.level)


@functools.cache
def _cos_k_errors(k: int) -> np.ndarray:
    return np.array([brdf_max_rel_error(n, k, "inflection") for n in range(1, N_MAX + 1)])


def check_claim(claim: Claim) -> ClaimCheck:
    return ClaimCheck(claim, claim_errors(claim))


def check_claims() -> list[ClaimCheck]:
    return [check_claim(c) for c in CLAIMS]


def _ranges(ns: list[int]) -> str:
    """1, 2, 3, 7 -> '1..3, 7'; [] -> 'none'."""
    if not ns:
        return "none"
    runs, start = [], ns[0]
    for prev, cur in zip(ns, [*ns[1:], None], strict=True):
        if cur != prev + 1:
            runs.append(str(start) if start == prev else f"{start}..{prev}")
            start = cur
    return ", ".join(runs)


def format_error(value: float) -> str:
    """A relative error in %, rounded up (4 decimals); 1000 % and more in exponent form."""
    if value >= 10.0:
        return f"{value * 100:.3g} %"
    return f"{fixed.format_up(value, 4, 100)} %"


def format_claims_table(checks: list[ClaimCheck] | None = None) -> str:
    """The claims against the exact worst errors (markdown; errors rounded up, "at" every n that
    reaches the worst to ``TIE_RTOL``)."""
    checks = check_claims() if checks is None else checks
    lines = [
        "| approximation | zone | thesis's claim | for n | worst, n = 1..1000 "
        "| worst, n = 2..1000 | worst, claim's n | claim holds | n where it fails "
        "| worst at the claim's digits |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for check in checks:
        c = check.claim
        zone = "epicentre" if c.level is None else "cos^n >= 1/e"
        cells = [
            f"{format_error(w)} at {_ranges(ns)}"
            for w, ns in (check.worst, check.worst_from(2), check.worst_in_range)
        ]
        fail = check.failing
        holds = "yes" if check.holds else f"no (from n = {fail[0]})"
        digits = f"{check.rounded} % ({'holds' if check.holds_rounded else 'fails'})"
        lines.append(
            f"| {c.label} | {zone} | {c.percent} % | {c.n_text} | {' | '.join(cells)} "
            f"| {holds} | {_ranges(fail)} | {digits} |"
        )
    return "\n".join(lines)
