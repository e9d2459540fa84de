"""factories"""
