"""Components that model effects found by ``hydro diagnose`` and not covered by the core
library: measurement lags on sensors, transport delay, valve play (backlash)."""
