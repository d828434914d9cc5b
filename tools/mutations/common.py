"""What the mutation scripts share: where things are, and the verdict on one run."""
import os
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SHARED = os.path.join(os.path.dirname(ROOT), 'shared', 'data')
POINTSHADE = os.path.join(ROOT, 'target/release/pointshade')
WORK = tempfile.mkdtemp(prefix='pointshade-mutations-')


def verdict(args, timeout=30):
    """Runs pointshade with `args`; None when it ended as bad input must (exit 0, or exit 2 with
    exactly one `error:` line besides warnings, no panic), else what went wrong."""
    try:
        r = subprocess.run([POINTSHADE] + args, capture_output=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return f'no answer in {timeout} s'
    err = r.stderr.decode(errors='replace')
    lines = [l for l in err.splitlines() if l.strip() and not l.startswith('warning')]
    if r.returncode in (0, 2) and (r.returncode == 0 or len(lines) == 1) and 'panick' not in err:
        return None
    return f'exit {r.returncode}: ' + err[:300].replace('\n', ' | ')
