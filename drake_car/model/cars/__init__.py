"""Shipped cars given by their hard points, each module with its sources."""
