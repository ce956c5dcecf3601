"""What /proc says of a process (Linux): for tests and runners that check that processes they
started have ended, and who their parent and process group are."""


def proc_stat(pid):
    """``(command name, state, parent pid, process group)`` of ``pid`` from /proc/<pid>/stat, or
    None once it is gone. The state is one letter: R running, S sleeping, Z a zombie (ended, not
    yet waited for by its parent), ..."""
    try:
        with open("/proc/%d/stat" % int(pid)) as f:
            head, rest = f.read().rsplit(")", 1)
    except (OSError, ValueError):
        return None
    fields = rest.split()
    return head.split("(", 1)[1], fields[0], int(fields[1]), int(fields[2])


def alive(pid):
    """True while ``pid`` runs: it exists and is not a zombie."""
    stat = proc_stat(pid)
    return stat is not None and stat[1] != "Z"
