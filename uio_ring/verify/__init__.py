"""Exact verification: certificates of designs (named identities with verdicts).

``Certificate`` and ``Check`` come from the ring; :func:`delay_uio_certificate`
builds the certificate of a Zheng–Bejarano delay UIO.
"""

from uio_ring.ring.certificate import Certificate, Check

__all__ = ["Certificate", "Check", "delay_uio_certificate"]


def __getattr__(name: str):  # lazy: keep ``import uio_ring.verify`` light
    if name == "delay_uio_certificate":
        from uio_ring.verify.delay_uio import delay_uio_certificate

        return delay_uio_certificate
    raise AttributeError(f"module 'uio_ring.verify' has no attribute {name!r}")
