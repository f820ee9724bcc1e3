"""Drive design: stage types, ratio splitting, tooth numbers, shaft speeds and torques, motor choice."""
