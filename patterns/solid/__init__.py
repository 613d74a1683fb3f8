"""SOLID principles: each one as a violating and a compliant design, side by side."""
