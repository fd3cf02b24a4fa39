"""The measured-like twitch shared by the Hatze tests: subject 3 at Table 2's theta, 0.8 s at 1 kHz (the
paper's sampling rate), one stimulus at 20 ms."""

import numpy as np

from neuromuscle.model.hatze_parameters import load_subjects, load_theta

THETA = load_theta()
SUBJECTS = load_subjects()
S3 = SUBJECTS["3"]
T_DATA = np.arange(0, 801) * 1e-3                     # 0.8 s at 1 kHz (the paper's sampling rate)
STIM = [0.02]
