"""The peak memory of a measuring subprocess, for the robustness tests' bounds (1 GB).

:data:`PEAK_RSS` is Python source that the tests' subprocess scripts start with: it defines
``peak_rss_kib()``, the process's own peak resident set size in KiB. It reads ``VmHWM`` from
``/proc/self/status``, which ``exec`` resets, and falls back to
``resource.getrusage(RUSAGE_SELF).ru_maxrss`` elsewhere: on Linux ``ru_maxrss`` carries over
the peak of the process that forked the child (measured: a child of an 800 MB parent reports
ru_maxrss 807312 KiB and VmHWM 8760 kB; a pytest worker's 705 MB was reported for a child whose
own peak was 169 MB), so alone it cannot bound the child's memory.
"""

PEAK_RSS = '''
def peak_rss_kib():
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1])
    except OSError:
        pass
    import resource
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
'''
