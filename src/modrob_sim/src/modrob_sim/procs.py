"""What /proc says of a process (Linux): for tests and runners that check that processes they
started have ended, and who their parent and process group are."""


def _stat(pid):
    """``(command name, [the fields after it])`` of /proc/<pid>/stat, or None once it is gone."""
    try:
        with open("/proc/%d/stat" % int(pid)) as f:
            head, rest = f.read().rsplit(")", 1)
    except (OSError, ValueError):
        return None
    return head.split("(", 1)[1], rest.split()


def proc_stat(pid):
    """``(command name, state, parent pid, process group)`` of ``pid`` from /proc/<pid>/stat, or
    None once it is gone. The state is one letter: R running, S sleeping, Z a zombie (ended, not
    yet waited for by its parent), ..."""
    stat = _stat(pid)
    if stat is None:
        return None
    name, fields = stat
    return name, fields[0], int(fields[1]), int(fields[2])


def start_time(pid):
    """When ``pid`` started (clock ticks after boot, /proc/<pid>/stat's field 22) while it runs, else
    None (gone, or a zombie): a pid and its start time name one process, also once the pid is reused."""
    stat = _stat(pid)
    if stat is None or stat[1][0] == "Z":
        return None
    return int(stat[1][19])


def alive(pid):
    """True while ``pid`` runs: it exists and is not a zombie."""
    stat = proc_stat(pid)
    return stat is not None and stat[1] != "Z"
