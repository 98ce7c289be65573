"""The batch user's layer: input decks, sweep expansion, the batch run, the HDF5 results
file, streamed histories, Dask, the ``railvti`` command and the results plots.

It knows the physics only through the case-type contract (:mod:`railvti.casetypes`); the
physics packages never import it. Nothing is imported here: ``import railvti.runner.cli``
must stay light (the command installs its signal handlers from its first instant).
"""
