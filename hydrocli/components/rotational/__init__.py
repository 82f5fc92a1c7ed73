"""Rotational mechanics for single joints (seed 001 §3.3, seed 002 Fig. 3)."""
