"""The translation between the wire models (``mechsynth_client.schemas``) and the engine's objects, one module per
capability: ``*_from`` functions build engine objects from requests, checking the rules that need the engine (a
mechanism that assembles, masses and loads that fit its output) and naming the field when one fails; ``*_out``
functions build answers from engine results. The plans, the studies and the library call these; the wire models
themselves know nothing of the engine.
"""
