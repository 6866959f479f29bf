"""Bit-exact golden models of the shading units (see README.md and ../shared/DESIGN.md)."""
