"""The bottom layer: array arithmetic that imports nothing else of noisevar.

- :mod:`~noisevar.numeric.fir`: the local-polynomial residual sequence and the centred
  filters that apply it, compiled (numba) or NumPy behind one switch
  (:data:`~noisevar.numeric.fir.USE_COMPILED`);
- :mod:`~noisevar.numeric.steps`: the level-jump (step) detector;
- :mod:`~noisevar.numeric.blocks`: sums, counts and medians per block, widened masks;
- :mod:`~noisevar.numeric.jit`: numba's ``njit`` when it is installed, else the identity.

Nothing is imported here: each module is loaded when it is used.
"""
