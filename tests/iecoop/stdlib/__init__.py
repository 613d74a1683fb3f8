"""Tests of the standard function blocks (iecoop.stdlib)."""
