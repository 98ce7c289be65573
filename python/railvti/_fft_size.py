"""FFT-friendly sizes: the smallest integer at or above n whose prime factors are 2, 3 and 5."""

from __future__ import annotations

__all__ = ["fft_size"]


def fft_size(n: int) -> int:
    """The smallest m >= n whose prime factors are 2, 3 and 5.

    FFTW transforms such sizes fast, while a large prime factor makes them several times
    slower (a 113 x 113 grid's product costs as much as a 225 x 225 one's, a 120 x 120
    grid's a quarter of it).

    Parameters
    ----------
    n : int
        The least size wanted (>= 1).

    Returns
    -------
    int
        The size.
    """
    m = max(int(n), 1)
    while True:
        k = m
        for f in (2, 3, 5):
            while k % f == 0:
                k //= f
        if k == 1:
            return m
        m += 1
