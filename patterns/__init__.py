"""The Gang-of-Four patterns and the SOLID principles as industrial automation scenarios on iecoop."""
