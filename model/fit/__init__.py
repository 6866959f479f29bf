# SPDX-License-Identifier: Apache-2.0
"""Fitting the units to a scene (docs/fit.md)."""
