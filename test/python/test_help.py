#!/usr/bin/env python3
"""Every tool of the repository answers --help with its usage and exit status 0: the C++ tools
(edge_slam_common/tools, ros_tools: built into the workspace), the ROS scripts, scripts/*.py,
the scripts behind the Makefile (scripts/*.sh) and the bench package's tools (python3 -m bench.X,
in the venv). The lists come from the source folders, so a new tool is covered by itself."""
import glob
import os
import subprocess
import sys
import unittest

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
BIN = os.path.join(ROOT, '.ws', 'devel', 'lib', 'edge_slam_common')
VENV_PYTHON = os.path.join(ROOT, '.venv', 'bin', 'python3')


def cpp_tools():
    return sorted(os.path.splitext(os.path.basename(p))[0]
                  for d in ('tools', 'ros_tools') for p in glob.glob(os.path.join(ROOT, 'edge_slam_common', d, '*.cpp')))


def bench_tools():
    """Modules of scripts/bench with a command line (an `if __name__ == "__main__"` block)."""
    return sorted(os.path.splitext(os.path.basename(p))[0] for p in glob.glob(os.path.join(ROOT, 'scripts', 'bench', '*.py'))
                  if '__main__' in open(p).read())


class HelpTest(unittest.TestCase):

    def check(self, cmd, want_usage=True, **kw):
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=60, stdin=subprocess.DEVNULL, **kw)
        text = r.stdout + r.stderr
        self.assertEqual(r.returncode, 0, '%s --help: exit %d\n%s' % (cmd[-2], r.returncode, text))
        self.assertTrue(text.strip(), '%s --help printed nothing' % cmd)
        if want_usage:
            self.assertIn('usage', text.lower(), '%s --help: no usage\n%s' % (cmd, text))
        return text

    def test_cpp_tools(self):
        tools = cpp_tools()
        self.assertIn('train_vocabulary', tools)
        for name in tools:
            with self.subTest(tool=name):
                self.check([os.path.join(BIN, name), '--help'])
        self.assertNotIn('needs a value', self.check([os.path.join(BIN, 'train_vocabulary'), '--help']))

    def test_ros_and_python_scripts(self):
        scripts = (glob.glob(os.path.join(ROOT, 'edge_slam_common', 'scripts', '*')) +
                   glob.glob(os.path.join(ROOT, 'edge_slam_mobile', 'scripts', '*')))
        scripts = [p for p in scripts if os.path.isfile(p) and os.access(p, os.X_OK)]
        self.assertGreaterEqual(len(scripts), 5)
        for path in sorted(scripts):
            with self.subTest(script=path):
                self.check([sys.executable, path, '--help'])
        for path in sorted(glob.glob(os.path.join(ROOT, 'scripts', '*.py'))):
            # scipy tools run in the venv; cv2 ones (Debian's, built on Debian's numpy) do not
            python = VENV_PYTHON if 'scipy' in open(path).read() else '/usr/bin/python3'
            with self.subTest(script=path):
                self.check([python, path, '--help'])

    def test_shell_scripts_print_their_header(self):
        paths = sorted(glob.glob(os.path.join(ROOT, 'scripts', '*.sh')) + glob.glob(os.path.join(ROOT, 'scripts', 'bench', '*.sh')))
        for path in paths:
            if os.path.basename(path) == 'common.sh':
                continue  # sourced, not run
            with self.subTest(script=path):
                self.check(['bash', path, '--help'], want_usage=False)

    def test_bench_package_tools(self):
        tools = bench_tools()
        self.assertIn('report', tools)
        for name in tools:
            with self.subTest(tool=name):
                self.check([VENV_PYTHON, '-m', 'bench.' + name, '--help'], cwd=os.path.join(ROOT, 'scripts'))


if __name__ == '__main__':
    unittest.main()
