"""ArduCopter's AUTOTUNE dance for multicopters (AC_AutoTune_Multi): the axes and the order they
are tuned in (axes.py), one twitch and what it measures (twitch.py), the rules that move the
gains after each twitch (rules.py), the gain sets the dance flies on (gains.py) and the dance
itself (dance.py). The flight mode (modes/autotune.py) flies what the dance asks."""
