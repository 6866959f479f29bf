# SPDX-License-Identifier: Apache-2.0
"""The thesis's family of float approximations of the BRDF cos^n d (docs/brdf.md).

Besides the patent's cos^k(a d) (``model.units.specular``), chapter 2 of the thesis
approximates cos^n d by a quadratic and a cubic in cos d, a piecewise cubic-and-bloom form, the
logarithmic form 2^(n log2 cos d) with an approximate 2^x, and the cosine-quadratic
(1 - (7n/16)(1 - cos d))^2.  Each is judged, like the patent's, by its largest relative error
against cos^n d in the highlight's epicentre (d from 0 to the inflection point
arctan(1/sqrt(n-1))), found exactly from the roots of the error's derivative (no
hardware in ``approx`` and ``claims``).

The fixed-point half: ``fixed`` (each form's bit-exact unit: widths, tables, numba kernels),
``fixed_accuracy`` (their exhaustive worst errors over every angle register value) and
``budget`` (the most accurate unit for n >= 8 within the patent's table bits).

Modules: ``approx`` (the forms, their coefficients and exact worst errors), ``claims`` (the
thesis's claimed bounds against those errors, and their table), ``fixed``, ``fixed_accuracy``,
``budget``.  This file only re-exports.
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
from model.units.brdf.budget import (
    Candidate,
    best_k_ranges,
    budget_bits,
    candidates,
    format_budget_table,
    winner,
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
from model.units.brdf.fixed import (
    COEFFICIENTS,
    CONFIGS,
    FixedConfig,
    angle_table,
    coefficient_values,
    coefficient_words,
    evaluate,
    log2_table,
    rom_images,
    table_bits,
)
from model.units.brdf.fixed_accuracy import (
    N_FROM,
    FixedAccuracy,
    epicentre_codes,
    fixed_accuracy,
    format_fixed_table,
    interval_ends,
)

__all__ = [
    "CLAIMS",
    "COEFFICIENTS",
    "CONFIGS",
    "COS_K",
    "CUBIC_Q",
    "FORMS",
    "GRID",
    "INV_E",
    "N_FROM",
    "TIE_RTOL",
    "Bloom",
    "Candidate",
    "Claim",
    "ClaimCheck",
    "Cubic",
    "FixedAccuracy",
    "FixedConfig",
    "Peak",
    "Quadratic",
    "angle_table",
    "approximate",
    "best_k_ranges",
    "bloom_coefficients",
    "budget_bits",
    "candidates",
    "check_claim",
    "check_claims",
    "check_n",
    "claim_errors",
    "coefficient_values",
    "coefficient_words",
    "cosine_quadratic_scale",
    "cubic_coefficients",
    "epicentre_codes",
    "evaluate",
    "exp2_approx",
    "fixed_accuracy",
    "format_budget_table",
    "format_claims_table",
    "format_error",
    "format_fixed_table",
    "interval_ends",
    "log2_table",
    "max_rel_error",
    "quadratic_coefficients",
    "rom_images",
    "table_bits",
    "winner",
    "worst_errors",
]
