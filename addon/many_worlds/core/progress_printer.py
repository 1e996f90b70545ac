"""A run's progress as people read it, without bpy: on a terminal one line rewritten in place, in
a log (a farm task's output file) at most one line every few seconds, and the last state always."""
import time

LOG_INTERVAL_S = 5.0


class ProgressPrinter:
    def __init__(self, stream, interval_s=LOG_INTERVAL_S, clock=time.monotonic):
        self.stream = stream
        self.interval_s = interval_s
        self.clock = clock
        self.in_place = stream.isatty()
        self.last_printed_at = None
        self.pending = None  # the newest words not printed yet (a log between two intervals)
        self.width = 0

    def update(self, words):
        if self.in_place:
            self.stream.write("\r" + words.ljust(self.width))
            self.width = max(self.width, len(words))
            self.stream.flush()
            self.last_printed_at = self.clock()
            return
        now = self.clock()
        if self.last_printed_at is None or now - self.last_printed_at >= self.interval_s:
            self.stream.write(words + "\n")
            self.stream.flush()
            self.last_printed_at = now
            self.pending = None
        else:
            self.pending = words

    def interrupt(self):
        """Before another line is printed: a line rewritten in place is ended first."""
        if self.in_place and self.width:
            self.stream.write("\n")
            self.width = 0

    def finish(self):
        """The last state is always printed; a line rewritten in place is ended."""
        if self.pending is not None:
            self.stream.write(self.pending + "\n")
            self.pending = None
        self.interrupt()
        self.stream.flush()
