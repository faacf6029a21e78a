"""Exact verification: certificates of designs (named identities with verdicts)."""

from uio_ring.ring.certificate import Certificate, Check

__all__ = ["Certificate", "Check"]
