"""Structural patterns: how function blocks are composed into larger units."""
