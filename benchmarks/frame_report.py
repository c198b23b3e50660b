#!/usr/bin/env python3
"""The whole tactile frame on one thread: each stage's median time and share, the frame rate
the loop sustains, and the same network's forward pass in PyTorch (one thread) beside the
OpenCV dnn one (docs/performance.md, "The whole tactile frame").

    /usr/bin/python3 benchmarks/frame_report.py build/release            # 5 repetitions
    /usr/bin/python3 benchmarks/frame_report.py build/release --quick    # a smoke run

It runs BUILD_DIR/benchmarks/lieservo_frame_bench (benchmarks/bench_frame.cpp) and times
examples/gdn/model.py's GDN, built with the deployed card's architecture, on the same image
(val/processed_images/image_1.png of the shared data set, resized as the card says; zeros
when the data set is not there). The PyTorch network has its initial weights: the deployed
weights exist only as ONNX, and a forward pass costs the same whatever the weights are.
Exit status: 0, 1 if a stage failed, 2 on bad usage or a missing program.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STAGES = [
    ('BM_FramePreprocess', 'preprocessing (crop, median, adaptive threshold, mask, 128x128)'),
    ('BM_FrameGdn', 'GDN forward pass (ONNX, OpenCV dnn)'),
    ('BM_FrameObservation', 'observation Gaussian (eq. 14, toObservation)'),
    ('BM_FrameFilter', 'Bayes filter step (Algorithm 2)'),
    ('BM_FrameController', 'servo controller step (eqs. 18-19)'),
    ('BM_FramePipeline', 'real-time pipeline, one 1 ms cycle'),
]


def run_bench(exe, reps, min_time):
    cmd = [exe, '--benchmark_format=json', '--benchmark_min_time=%g' % min_time,
           '--benchmark_repetitions=%d' % reps, '--benchmark_report_aggregates_only=%s' % ('true' if reps > 1 else 'false')]
    out = subprocess.run(cmd, check=False, capture_output=True, text=True)
    if out.returncode != 0:
        sys.stderr.write(out.stderr)
        sys.exit(1)
    data = json.loads(out.stdout)
    times = {}
    for b in data['benchmarks']:
        if b.get('error_occurred'):
            sys.stderr.write('%s: %s\n' % (b['name'], b.get('error_message', 'failed')))
            sys.exit(1)
        if reps > 1 and b.get('aggregate_name') != 'median':
            continue
        scale = {'ns': 1e-3, 'us': 1.0, 'ms': 1e3, 's': 1e6}[b['time_unit']]
        times[b['run_name']] = b['real_time'] * scale  # µs
    return times, data['context']


def torch_forward_us(reps, seconds):
    sys.path.insert(0, os.path.join(ROOT, 'examples', 'gdn'))
    import numpy as np
    import torch
    import dataset
    import model
    torch.set_num_threads(1)
    net = model.build('gdn').eval()
    image = os.path.join(ROOT, '..', 'shared', 'data', 'tactip', 'val', 'processed_images', 'image_1.png')
    if os.path.isfile(image):
        x = dataset.to_input(dataset.load_image(image))[None, None]
        source = image
    else:
        x = np.zeros((1, 1, 128, 128), np.float32)
        source = 'zeros (%s is not there)' % image
    x = torch.from_numpy(np.ascontiguousarray(x))
    per_call = []
    with torch.no_grad():
        for _ in range(5):
            net(x)  # warm-up
        for _ in range(reps):
            n, t0 = 0, time.perf_counter()
            while time.perf_counter() - t0 < seconds:
                net(x)
                n += 1
            per_call.append((time.perf_counter() - t0) / n * 1e6)
    return statistics.median(per_call), torch.__version__, source


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('build_dir', help='a build folder holding benchmarks/lieservo_frame_bench')
    ap.add_argument('--quick', action='store_true', help='one short repetition (a smoke run)')
    a = ap.parse_args(argv)
    exe = os.path.join(a.build_dir, 'benchmarks', 'lieservo_frame_bench')
    if not os.access(exe, os.X_OK):
        sys.stderr.write('frame_report.py: no %s (build the release preset with OpenCV)\n' % exe)
        return 2
    reps, min_time, seconds = (1, 0.001, 0.05) if a.quick else (5, 0.5, 1.0)
    times, context = run_bench(exe, reps, min_time)
    torch_us, torch_version, torch_source = torch_forward_us(reps, seconds)

    print('The whole tactile frame on one thread (%s of %d repetitions; %s)' %
          ('median' if reps > 1 else 'one', reps, context.get('host_name', 'this machine')))
    print('image: %s' % context.get('frame_image', '?'))
    total = sum(times[name] for name, _ in STAGES)
    print('%-64s %12s %7s' % ('stage', 'time (us)', 'share'))
    for name, label in STAGES:
        print('%-64s %12.2f %6.1f%%' % (label, times[name], 100 * times[name] / total))
    whole = times['BM_FrameWhole']
    print('%-64s %12.2f' % ('sum of the stages', total))
    print('%-64s %12.2f' % ('the whole frame, measured in one loop', whole))
    print('frame rate the loop sustains on one thread: %.0f Hz (the paper controls at 20 Hz)' % (1e6 / whole))
    print('the 1 kHz thread: %.2f us per cycle, %.3f %% of one core' %
          (times['BM_FramePipeline'], times['BM_FramePipeline'] / 10))
    print('the same GDN in PyTorch %s (one thread, initial weights; input: %s): %.0f us per forward pass, '
          '%.2fx the OpenCV dnn pass' % (torch_version, torch_source, torch_us, torch_us / times['BM_FrameGdn']))
    return 0


if __name__ == '__main__':
    sys.exit(main())
