# Placeholder replaced below
