"""Progress display for long runs: tqdm when installed, otherwise a line on stderr."""
import sys


class _Line:
    def __init__(self):
        self.shown = -1

    def update(self, fraction, sim_time):
        pct = int(100 * fraction)
        if pct != self.shown:
            self.shown = pct
            sys.stderr.write(f"\rhardsphere: {pct}% done, simulated time {sim_time:g}   ")
            sys.stderr.flush()

    def close(self):
        if self.shown >= 0:
            sys.stderr.write("\n")


class _Tqdm:
    def __init__(self, tqdm):
        self.bar = tqdm(total=1000, unit="", bar_format="{l_bar}{bar}| {elapsed}<{remaining}")
        self.done = 0

    def update(self, fraction, sim_time):
        n = int(1000 * fraction)
        self.bar.update(n - self.done)
        self.done = n
        self.bar.set_postfix_str(f"t={sim_time:g}", refresh=False)

    def close(self):
        self.bar.close()


def progress_bar():
    """An object with update(fraction, sim_time) and close(): a tqdm bar if tqdm is installed."""
    try:
        from tqdm import tqdm
    except ImportError:
        return _Line()
    return _Tqdm(tqdm)
