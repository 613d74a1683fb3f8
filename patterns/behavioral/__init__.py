"""Behavioral patterns: how function blocks share work and react across scan cycles."""
