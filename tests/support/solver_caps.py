"""The time cap of a solver call whose verdict a test asserts (issue 42).

A test that asserts an answer (solved, a count of solved targets, two runs alike, a status reached
after the whole search) must not let the solver's time cap decide it: on a loaded machine a cap of
50 ms, 0.5 s or even 5 s is reached, and the answer becomes ``timeout``. Such calls pass
:data:`NO_CAP`; their work stays bounded by the solver's own counts (starts, steps, attempts). A
test about the cap itself uses a cap every machine reaches (0 or 1 us) or a clock of its own.
"""

#: A cap no machine's load reaches [s]: ten minutes, for calls of milliseconds to a second.
NO_CAP = 600.0
