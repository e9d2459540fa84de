"""melfa"""
