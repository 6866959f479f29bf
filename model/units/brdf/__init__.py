# SPDX-License-Identifier: Apache-2.0
"""The thesis's family of float approximations of the BRDF cos^n d (docs/brdf.md).

Besides the patent's cos^k(a d) (``model.units.specular``), chapter 2 of the thesis
approximates cos^n d by a quadratic and a cubic in cos d, a piecewise cubic-and-bloom form, the
logarithmic form 2^(n log2 cos d) with an approximate 2^x, and the cosine-quadratic
(1 - (7n/16)(1 - cos d))^2.  Each is judged, like the patent's, by its largest relative error
against cos^n d in the highlight's epicentre (d from 0 to the inflection point
arctan(1/sqrt(n-1))), found exactly from the roots of the error's derivative.  Float only: no
fixed point, no hardware.

Modules: ``approx`` (the forms, their coefficients and exact worst errors), ``claims`` (the
thesis's claimed bounds against those errors, and their table).  This file only re-exports.
"""

from model.units.brdf.approx import (
    CUBIC_Q,
    FORMS,
    GRID,
    Bloom,
    Cubic,
    Peak,
    Quadratic,
    approximate,
    bloom_coefficients,
    check_n,
    cosine_quadratic_scale,
    cubic_coefficients,
    exp2_approx,
    max_rel_error,
    quadratic_coefficients,
    worst_errors,
)
from model.units.brdf.claims import (
    CLAIMS,
    COS_K,
    INV_E,
    TIE_RTOL,
    Claim,
    ClaimCheck,
    check_claim,
    check_claims,
    claim_errors,
    format_claims_table,
    format_error,
)

__all__ = [
    "CLAIMS",
    "COS_K",
    "CUBIC_Q",
    "FORMS",
    "GRID",
    "INV_E",
    "TIE_RTOL",
    "Bloom",
    "Claim",
    "ClaimCheck",
    "Cubic",
    "Peak",
    "Quadratic",
    "approximate",
    "bloom_coefficients",
    "check_claim",
    "check_claims",
    "check_n",
    "claim_errors",
    "cosine_quadratic_scale",
    "cubic_coefficients",
    "exp2_approx",
    "format_claims_table",
    "format_error",
    "max_rel_error",
    "quadratic_coefficients",
    "worst_errors",
]
