"""Exact algebra over Q[δ]: polynomial matrices and their normal forms."""
